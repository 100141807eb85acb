// The `.scene` text format (docs/scene-format.md) and light specifications ("point:1,2,3,...").
// A scene file is read line by line; `mesh` and `polygon` open an object that the following
// property lines (name, color, transforms, vertices) describe, until the next top-level statement.
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/instancing.hpp"
#include "hsr/limits.hpp"
#include "hsr/scene_builder.hpp"
#include "hsr/scene_file.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>

namespace hsr {
namespace {

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

std::optional<float> to_float(std::string_view text) {
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    double value = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    if (!std::isfinite(value) || std::fabs(value) > 3.0e38) return std::nullopt;
    return static_cast<float>(value);
}

std::vector<std::string_view> split(std::string_view text, char separator) {
    std::vector<std::string_view> parts;
    std::size_t start = 0;
    while (true) {
        std::size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
        if (end == std::string_view::npos) return parts;
        start = end + 1;
    }
}

// "r/g/b" with channels in [0, 1], or "#rrggbb".
std::optional<glm::vec3> parse_color_text(std::string_view text) {
    if (!text.empty() && text.front() == '#') {
        if (text.size() != 7) return std::nullopt;
        glm::vec3 color;
        for (int k = 0; k < 3; ++k) {
            unsigned value = 0;
            auto [end, ec] = std::from_chars(text.data() + 1 + 2 * k, text.data() + 3 + 2 * k, value, 16);
            if (ec != std::errc() || end != text.data() + 3 + 2 * k) return std::nullopt;
            color[k] = static_cast<float>(value) / 255.0f;
        }
        return color;
    }
    std::vector<std::string_view> parts = split(text, '/');
    if (parts.size() != 3) return std::nullopt;
    glm::vec3 color;
    for (int k = 0; k < 3; ++k) {
        std::optional<float> v = to_float(parts[static_cast<std::size_t>(k)]);
        if (!v || *v < 0.0f || *v > 1.0f) return std::nullopt;
        color[k] = *v;
    }
    return color;
}

// ---------------------------------------------------------------------------------------------

struct Statement {
    std::size_t line;
    std::vector<std::string> words;  // quotes removed
};

class SceneParser {
public:
    SceneParser(const std::filesystem::path& file, const ReadPolicy& policy, Language language)
        : file_(file), folder_(file.parent_path()), policy_(policy), language_(language), builder_(language) {}

    SceneFile parse() {
        std::error_code ec;
        if (!std::filesystem::exists(file_, ec)) throw Error(say(language_, "{}: no such file", "{}: нет такого файла", path_text()));
        if (!std::filesystem::is_regular_file(file_, ec))  // a pipe or /dev/zero would be read without end
            throw Error(say(language_, "{}: is not a regular file, not a scene file", "{}: это не обычный файл и не файл сцены",
                            path_text()));
        const std::uintmax_t size = std::filesystem::file_size(file_, ec);
        if (ec) throw Error(say(language_, "{}: cannot read the file size", "{}: не удалось узнать размер файла", path_text()));
        check_limit(&Limits::model_bytes, size, path_text(), language_);
        // The repeat line first, wherever it stands, so that each mesh is checked against the
        // triangles its copies will draw as soon as it is loaded.
        for_each_statement([&](const Statement& s) {
            if (s.words[0] == "repeat") repeat(s);
        });
        for_each_statement([&](const Statement& s) {
            if (s.words[0] == "repeat")
                finish_object();
            else
                handle(s);
        });
        finish_object();
        if (builder_.object_count() == 0)
            throw Error(say(language_, "{}: the scene has no mesh or polygon",
                            "{}: в сцене нет ни модели (mesh), ни многоугольника (polygon)",
                            path_text()));
        try {
            result_.scene = builder_.build();
            if (std::any_of(opacity_.begin(), opacity_.end(), [](float a) { return a < 1.0f; }))
                result_.scene.object_opacity = opacity_;
        } catch (const Error& e) {
            rethrow_with_message(e, fmt::format("{}: {}", path_text(), printable(e.what(), std::string::npos)));
        }
        if (repeat_) result_.scene = make_instance_grid(result_.scene, *repeat_);
        if (result_.pixel_camera && !result_.width) {
            glm::vec3 top = result_.scene.bounds_max;
            if (!(top.x >= 1.0f && top.y >= 1.0f && top.x <= 16384.0f && top.y <= 16384.0f))
                throw Error(say(language_, "{}: `camera pixel` needs `size W H` here (the scene's top right corner is at {}, {})",
                                "{}: для `camera pixel` здесь нужна строка `size W H` (правый верхний угол сцены — в точке {}, {})",
                                path_text(), top.x, top.y));
            result_.width = static_cast<uint32_t>(std::ceil(top.x));
            result_.height = static_cast<uint32_t>(std::ceil(top.y));
        }
        return std::move(result_);
    }

private:
    // The message quotes the file's words through printable(); what a mesh file's reader says is
    // made one line here.
    [[noreturn]] void fail(std::size_t line, const std::string& message) const {
        throw Error("{}:{}: {}", path_text(), line, printable(message, std::string::npos));
    }
    // The same for an error caught on the way, which keeps its type (a LimitError stays one).
    [[noreturn]] void fail(std::size_t line, const Error& cause) const {
        rethrow_with_message(cause, fmt::format("{}:{}: {}", path_text(), line, printable(cause.what(), std::string::npos)));
    }

    std::string path_text() const { return printable(file_.string(), kMaxQuotedPathChars); }

    template <class Handle>
    void for_each_statement(Handle handle) const {
        std::ifstream in(file_);
        if (!in) throw Error(say(language_, "{}: cannot open the file for reading", "{}: не удалось открыть файл для чтения", path_text()));
        std::string text;
        std::size_t number = 0;
        while (std::getline(in, text)) {
            ++number;
            const Statement statement{number, split_words(text, number)};
            if (!statement.words.empty()) handle(statement);
        }
    }

    // Words separated by spaces; "double quotes" keep spaces; '#' at the start of a word starts a
    // comment (so `color=#rrggbb` inside a word is not one).
    std::vector<std::string> split_words(const std::string& text, std::size_t line) const {
        std::vector<std::string> words;
        std::size_t i = 0;
        while (i < text.size()) {
            while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
            if (i >= text.size() || text[i] == '#') break;
            std::string word;
            if (text[i] == '"') {
                std::size_t close = text.find('"', i + 1);
                if (close == std::string::npos) fail(line, say(language_, "unterminated quote", "кавычка не закрыта"));
                word = text.substr(i + 1, close - i - 1);
                i = close + 1;
            } else {
                while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) word += text[i++];
            }
            words.push_back(std::move(word));
        }
        return words;
    }

    // `what` names the number for the message, in the reader's language.
    float number(const Statement& s, std::size_t index, const std::string& what) const {
        std::optional<float> v = to_float(s.words[index]);
        if (!v)
            fail(s.line, say(language_, "{} '{}' is not a finite number", "{}: «{}» не является конечным числом", what,
                             printable(s.words[index])));
        return *v;
    }

    glm::vec3 vector3(const Statement& s, std::size_t first, const std::string& what) const {
        return {number(s, first, what), number(s, first + 1, what), number(s, first + 2, what)};
    }

    // `usage`: the statement's form, in the reader's language.
    void expect_count(const Statement& s, std::size_t count, const std::string& usage) const {
        if (s.words.size() != count) fail(s.line, say(language_, "expected: {}", "ожидалось: {}", usage));
    }

    glm::vec3 color(const Statement& s, const std::string& usage) const {
        expect_count(s, 4, usage);
        glm::vec3 c = vector3(s, 1, say(language_, "colour channel", "компонента цвета"));
        for (int k = 0; k < 3; ++k)
            if (c[k] < 0.0f || c[k] > 1.0f)
                fail(s.line, say(language_, "colour channel {} is outside [0, 1]", "компонента цвета {} вне отрезка [0, 1]", c[k]));
        return c;
    }

    void handle(const Statement& s) {
        const std::string& keyword = s.words[0];
        if (keyword == "mesh") {
            finish_object();
            expect_count(s, 2, say(language_, "mesh <file>  (quote a path with spaces)", "mesh <файл>  (путь с пробелами — в кавычках)"));
            open_object(s, Kind::mesh);
            object_.path = s.words[1];
            if (!policy_.allows(mesh_path(object_.path)))
                fail(s.line, say(language_, "mesh '{}' lies outside {}", "файл модели «{0}» лежит вне папок, из которых разрешено читать",
                                 printable(s.words[1]), policy_.description()));
        } else if (keyword == "polygon") {
            finish_object();
            expect_count(s, 1, say(language_, "polygon  (then color and vertex lines)", "polygon  (а за ней — строки color и vertex)"));
            open_object(s, Kind::polygon);
        } else if (keyword == "background") {
            finish_object();
            if (result_.background) fail(s.line, say(language_, "background is given twice", "фон (background) задан дважды"));
            result_.background = color(s, say(language_, "background <r> <g> <b>  (each in [0, 1])",
                                              "background <r> <g> <b>  (каждая компонента — из [0, 1])"));
        } else if (keyword == "size") {
            finish_object();
            expect_count(s, 3, say(language_, "size <width> <height>", "size <ширина> <высота>"));
            if (result_.width) fail(s.line, say(language_, "size is given twice", "размер (size) задан дважды"));
            uint32_t size[2];
            for (int k = 0; k < 2; ++k) {
                const std::string& word = s.words[static_cast<std::size_t>(k) + 1];
                auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), size[k]);
                if (ec != std::errc() || end != word.data() + word.size() || size[k] == 0 || size[k] > 16384)
                    fail(s.line, say(language_, "image size '{}' is not a whole number in [1, 16384]",
                                     "размер изображения «{}» — не целое число из [1, 16384]", printable(word)));
            }
            result_.width = size[0];
            result_.height = size[1];
        } else if (keyword == "samples") {
            finish_object();
            expect_count(s, 2, say(language_, "samples <n>  (1, 2, 4, 8 or 16)", "samples <n>  (1, 2, 4, 8 или 16)"));
            if (result_.samples) fail(s.line, say(language_, "samples is given twice", "число выборок (samples) задано дважды"));
            const std::string& word = s.words[1];
            uint32_t n = 0;
            auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), n);
            if (ec != std::errc() || end != word.data() + word.size() || !(n == 1 || n == 2 || n == 4 || n == 8 || n == 16))
                fail(s.line, say(language_, "samples '{}': expected 1, 2, 4, 8 or 16", "samples «{}»: ожидалось 1, 2, 4, 8 или 16",
                                 printable(word)));
            result_.samples = n;
        } else if (keyword == "camera") {
            finish_object();
            camera(s);
        } else if (keyword == "clip-plane" || keyword == "section") {
            finish_object();
            const bool section = keyword == "section";
            expect_count(s, section ? 2 : 5,
                         section ? say(language_, "section <z>  (keeps z <= z)", "section <z>  (остаётся то, где z <= z)")
                                 : say(language_, "clip-plane <a> <b> <c> <d>  (keeps a*x + b*y + c*z + d >= 0)",
                                       "clip-plane <a> <b> <c> <d>  (остаётся то, где a*x + b*y + c*z + d >= 0)"));
            if (result_.clip_planes.size() == HSR_MAX_CLIP_PLANES)
                fail(s.line, say(language_, "more than {} clip planes and sections",
                                 "больше {} плоскостей отсечения (clip-plane и section)",
                                 HSR_MAX_CLIP_PLANES));
            const std::string plane_what = say(language_, "clip plane", "коэффициент плоскости отсечения");
            const glm::vec4 plane = section ? section_plane(number(s, 1, say(language_, "section z", "z сечения")))
                                            : glm::vec4(vector3(s, 1, plane_what), number(s, 4, plane_what));
            if (plane.x == 0.0f && plane.y == 0.0f && plane.z == 0.0f)
                fail(s.line, say(language_, "the clip plane's normal (a, b, c) is zero", "нормаль плоскости отсечения (a, b, c) нулевая"));
            result_.clip_planes.push_back(plane);
        } else if (keyword == "light") {
            finish_object();
            if (s.words.size() < 2)
                fail(s.line, say(language_, "expected: light point:x,y,z  or  light dir:x,y,z  (then ,key=value ...)",
                                 "ожидалось: light point:x,y,z  или  light dir:x,y,z  (а дальше — ,ключ=значение ...)"));
            std::string spec;
            for (std::size_t i = 1; i < s.words.size(); ++i) spec += s.words[i];
            try {
                check_limit(&Limits::lights, result_.lights.size() + 1, "", language_);
                result_.lights.push_back(parse_light_spec(spec, language_));
            } catch (const Error& e) {
                fail(s.line, e);
            }
        } else if (keyword == "name" || keyword == "color" || keyword == "opacity" || keyword == "translate" || keyword == "rotate" ||
                   keyword == "scale" || keyword == "crease" || keyword == "vertex") {
            property(s);
        } else {
            fail(s.line, say(language_, "unknown statement '{}'", "неизвестная инструкция «{}»", printable(keyword)));
        }
    }

    // repeat <columns> <rows> <layers> [gap <g>] [jitter <degrees>]: the whole scene becomes a grid
    // of instances (make_instance_grid), stored once.
    void repeat(const Statement& s) {
        if (repeat_) fail(s.line, say(language_, "repeat is given twice", "repeat задан дважды"));
        if (s.words.size() < 4)
            fail(s.line, say(language_, "expected: repeat <columns> <rows> <layers> [gap <g>] [jitter <degrees>]",
                             "ожидалось: repeat <столбцы> <ряды> <слои> [gap <g>] [jitter <градусы>]"));
        InstanceGrid grid;
        uint32_t* counts[3] = {&grid.columns, &grid.rows, &grid.layers};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::string& word = s.words[k + 1];
            auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), *counts[k]);
            if (ec != std::errc() || end != word.data() + word.size() || *counts[k] == 0 || *counts[k] > 100000)
                fail(s.line, say(language_, "repeat count '{}' is not a whole number in [1, 100000]",
                                 "число копий «{}» — не целое число из [1, 100000]", printable(word)));
        }
        try {
            check_limit(&Limits::instances, uint64_t(grid.columns) * grid.rows * grid.layers, "", language_);
        } catch (const Error& e) {
            fail(s.line, e);
        }
        for (std::size_t i = 4; i < s.words.size(); i += 2) {
            const std::string& key = s.words[i];
            if (key != "gap" && key != "jitter")
                fail(s.line, say(language_, "unknown repeat setting '{}' (gap, jitter)",
                                 "неизвестный параметр repeat «{}» (есть gap и jitter)",
                                 printable(key)));
            if (i + 1 >= s.words.size())
                fail(s.line, say(language_, "repeat setting '{}' needs a value", "у параметра repeat «{}» нет значения", key));
            const float value = number(s, i + 1, key);
            if (key == "gap") {
                if (value < 0.0f) fail(s.line, say(language_, "gap must be 0 or more", "gap должен быть не меньше 0"));
                grid.gap = value;
            } else {
                if (value < 0.0f || value > 180.0f)
                    fail(s.line, say(language_, "jitter must be between 0 and 180 degrees", "jitter должен быть от 0 до 180 градусов"));
                grid.yaw_jitter_degrees = value;
            }
        }
        repeat_ = grid;
    }

    void camera(const Statement& s) {
        if (camera_line_ != 0)
            fail(s.line, say(language_, "the camera is already set on line {}", "камера уже задана в строке {}", camera_line_));
        camera_line_ = s.line;
        if (s.words.size() >= 2 && s.words[1] == "pixel") {
            expect_count(s, 2, "camera pixel");
            result_.pixel_camera = true;
            return;
        }
        const bool look_at = s.words.size() >= 2 && s.words[1] == "look-at";
        if (s.words.size() < 2 || (s.words[1] != "orbit" && !look_at))
            fail(s.line, say(language_,
                             "expected: camera pixel  or  camera orbit [yaw <deg>] [pitch <deg>] [zoom <z>] [fov <deg>] "
                             "[orthographic|perspective]  or  camera look-at eye <x y z> [target <x y z>] [up <x y z>] "
                             "[fov <deg>] [zoom <z>] [orthographic|perspective]",
                             "ожидалось: camera pixel  или  camera orbit [yaw <градусы>] [pitch <градусы>] [zoom <z>] "
                             "[fov <градусы>] [orthographic|perspective]  или  camera look-at eye <x y z> [target <x y z>] "
                             "[up <x y z>] [fov <градусы>] [zoom <z>] [orthographic|perspective]"));
        const char* settings = look_at ? "eye, target, up, fov, zoom, orthographic, perspective"
                                       : "yaw, pitch, zoom, fov, orthographic, perspective";
        LookAt view;
        bool eye_given = false;
        for (std::size_t i = 2; i < s.words.size(); ++i) {
            const std::string& key = s.words[i];
            if (key == "orthographic" || key == "perspective") {
                result_.orthographic = key == "orthographic";
                continue;
            }
            const bool vector = key == "eye" || key == "target" || key == "up";
            const bool known = key == "zoom" || key == "fov" || (look_at ? vector : key == "yaw" || key == "pitch");
            if (!known)
                fail(s.line, say(language_, "unknown camera setting '{}' ({})", "неизвестный параметр камеры «{}» (есть {})",
                                 printable(key), settings));
            if (i + (vector ? 3 : 1) >= s.words.size())
                fail(s.line, say(language_, "camera setting '{}' needs {}", "параметру камеры «{}» нужно {}", key,
                                 vector ? "x y z" : say(language_, "a value", "значение")));
            if (vector) {
                const glm::vec3 v = vector3(s, i + 1, key);
                i += 3;
                if (key == "eye") view.eye = v, eye_given = true;
                if (key == "target") view.target = v;
                if (key == "up") view.up = v;
                continue;
            }
            float value = number(s, ++i, key);
            if (key == "yaw") result_.yaw_degrees = value;
            if (key == "pitch") result_.pitch_degrees = value;
            if (key == "zoom") {
                if (value <= 0.0f) fail(s.line, say(language_, "zoom must be greater than 0", "zoom должен быть больше 0"));
                result_.zoom = value;
            }
            if (key == "fov") {
                if (!(value > 0.0f && value < 180.0f))
                    fail(s.line, say(language_, "fov must be between 0 and 180 degrees", "fov должен быть строго между 0 и 180 градусами"));
                result_.fov_y_degrees = value;
            }
        }
        if (look_at && !eye_given) fail(s.line, say(language_, "camera look-at needs eye <x y z>", "для camera look-at нужен eye <x y z>"));
        if (look_at) result_.look_at = view;
    }

    std::optional<InstanceGrid> repeat_;

    enum class Kind { none, mesh, polygon };

    struct PendingObject {
        Kind kind = Kind::none;
        std::size_t line = 0;
        std::string path;
        MeshOptions options;
        bool has_name = false, has_color = false, has_crease = false, has_opacity = false;
        float opacity = 1.0f;
        std::vector<glm::vec3> vertices;
    };

    void open_object(const Statement& s, Kind kind) {
        object_ = PendingObject{};
        object_.kind = kind;
        object_.line = s.line;
    }

    void property(const Statement& s) {
        const std::string& keyword = s.words[0];
        if (object_.kind == Kind::none)
            fail(s.line, say(language_, "'{}' must follow a mesh or polygon line",
                             "«{}» должна стоять после строки mesh или polygon", keyword));
        MeshOptions& options = object_.options;
        if (keyword == "name") {
            expect_count(s, 2, say(language_, "name <name>  (quote a name with spaces)", "name <имя>  (имя с пробелами — в кавычках)"));
            if (object_.has_name) fail(s.line, say(language_, "the object already has a name", "у объекта уже есть имя"));
            object_.has_name = true;
            options.name = s.words[1];
        } else if (keyword == "color") {
            if (object_.has_color) fail(s.line, say(language_, "the object already has a colour", "у объекта уже задан цвет"));
            object_.has_color = true;
            options.color = color(s, say(language_, "color <r> <g> <b>  (each in [0, 1])",
                                         "color <r> <g> <b>  (каждая компонента — из [0, 1])"));
            options.color_given = true;
        } else if (keyword == "opacity") {
            expect_count(s, 2, say(language_, "opacity <a>  (0 invisible .. 1 opaque)", "opacity <a>  (0 — не виден .. 1 — непрозрачен)"));
            if (object_.has_opacity) fail(s.line, say(language_, "the object already has an opacity",
                                                      "у объекта уже задана непрозрачность"));
            object_.has_opacity = true;
            object_.opacity = number(s, 1, say(language_, "opacity", "непрозрачность"));
            if (!(object_.opacity >= 0.0f && object_.opacity <= 1.0f))
                fail(s.line, say(language_, "opacity must be within [0, 1]", "непрозрачность должна быть из [0, 1]"));
        } else if (keyword == "translate") {
            expect_count(s, 4, "translate <x> <y> <z>");
            options.transform = glm::translate(glm::mat4(1.0f), vector3(s, 1, say(language_, "offset", "сдвиг"))) * options.transform;
        } else if (keyword == "rotate") {
            expect_count(s, 5, say(language_, "rotate <degrees> <axis x> <axis y> <axis z>", "rotate <градусы> <ось x> <ось y> <ось z>"));
            float degrees = number(s, 1, say(language_, "angle", "угол"));
            glm::vec3 axis = vector3(s, 2, say(language_, "axis component", "компонента оси"));
            if (glm::length(axis) == 0.0f) fail(s.line, say(language_, "the rotation axis is zero", "ось поворота нулевая"));
            options.transform = glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)) * options.transform;
        } else if (keyword == "scale") {
            if (s.words.size() != 2 && s.words.size() != 4)
                fail(s.line, say(language_, "expected: scale <s>  or  scale <x> <y> <z>", "ожидалось: scale <s>  или  scale <x> <y> <z>"));
            const std::string what = say(language_, "scale", "коэффициент масштаба");
            glm::vec3 factor = s.words.size() == 2 ? glm::vec3(number(s, 1, what)) : vector3(s, 1, what);
            if (factor.x == 0.0f || factor.y == 0.0f || factor.z == 0.0f)
                fail(s.line, say(language_, "a scale factor is zero", "коэффициент масштаба равен нулю"));
            options.transform = glm::scale(glm::mat4(1.0f), factor) * options.transform;
        } else if (keyword == "crease") {
            if (object_.kind != Kind::mesh) fail(s.line, say(language_, "crease applies to meshes only",
                                                             "crease относится только к моделям (mesh)"));
            expect_count(s, 2, say(language_, "crease <degrees>", "crease <градусы>"));
            if (object_.has_crease) fail(s.line, say(language_, "the mesh already has a crease angle", "у модели уже задан угол излома"));
            object_.has_crease = true;
            options.crease_angle_degrees = number(s, 1, say(language_, "crease angle", "угол излома"));
            if (options.crease_angle_degrees < 0.0f || options.crease_angle_degrees > 180.0f)
                fail(s.line, say(language_, "the crease angle must be within [0, 180] degrees",
                                 "угол излома должен быть от 0 до 180 градусов"));
        } else if (keyword == "vertex") {
            if (object_.kind != Kind::polygon)
                fail(s.line, say(language_, "vertex lines belong to a polygon", "строки vertex относятся к многоугольнику (polygon)"));
            expect_count(s, 4, "vertex <x> <y> <z>");
            object_.vertices.push_back(vector3(s, 1, say(language_, "coordinate", "координата")));
        }
    }

    // A mesh line's file: relative paths resolve against the scene file's folder.
    std::filesystem::path mesh_path(const std::string& text) const {
        std::filesystem::path path(text);
        if (path.is_relative()) path = folder_ / path;
        return path.lexically_normal();
    }

    void finish_object() {
        PendingObject object = std::move(object_);
        object_ = PendingObject{};
        try {
            if (object.kind == Kind::mesh) {
                const std::filesystem::path path = mesh_path(object.path);
                // A file named again is copied, not read again: many lines of one large mesh reach
                // the triangle limits in moments.
                const auto read = mesh_objects_.find(path.string());
                const std::size_t before = builder_.object_count();
                if (read == mesh_objects_.end()) {
                    read_mesh_file(path, object.options);
                    mesh_objects_.emplace(path.string(), std::pair(before, builder_.object_count() - before));
                } else {
                    const auto [first, count] = read->second;
                    for (std::size_t part = 0; part < count; ++part) {
                        MeshOptions options = object.options;
                        // as add_model_file names it: the file's stem, and each OBJ group's name after it
                        const std::string& made = builder_.objects()[first + part].options.name;
                        const std::string group = count > 1 ? made.substr(made.rfind('/')) : std::string();
                        if (options.name.empty()) options.name = path.stem().string();
                        options.name += group;
                        builder_.add_copy(first + part, options);
                    }
                }
                for (std::size_t added = before + 1; added < builder_.object_count(); ++added)
                    opacity_.push_back(object.opacity);
            } else if (object.kind == Kind::polygon) {
                if (object.vertices.size() < 3)
                    fail(object.line, say(language_, "the polygon has {} vertex lines; it needs at least 3",
                                          "строк vertex у многоугольника: {}, а нужно не меньше трёх", object.vertices.size()));
                const glm::mat4& m = object.options.transform;
                for (glm::vec3& v : object.vertices) v = glm::vec3(m * glm::vec4(v, 1.0f));
                if (glm::determinant(glm::mat3(m)) < 0.0f)  // a mirror keeps the same side in front
                    std::reverse(object.vertices.begin(), object.vertices.end());
                builder_.add_polygon(object.vertices, object.options.color, object.options.name);
            }
            if (object.kind != Kind::none) {
                opacity_.push_back(object.opacity);
                check_triangles();
            }
        } catch (const Error& e) {
            if (std::string_view(e.what()).starts_with(path_text() + ":")) throw;
            fail(object.line, e);
        }
    }

    // The model file of a mesh line. That it is there is checked here, so that a name mistyped in the
    // scene is told in the scene's language (in English as the model reader says it); what the file
    // itself holds wrong stays the model reader's English, framed in the scene's language.
    void read_mesh_file(const std::filesystem::path& path, const MeshOptions& options) {
        const std::string shown = printable(path.string(), kMaxQuotedPathChars);
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) throw Error(say(language_, "{}: no such file", "{}: нет такого файла", shown));
        if (std::filesystem::is_directory(path, ec))
            throw Error(say(language_, "{}: is a folder, not a model file", "{}: это папка, а не файл модели", shown));
        try {
            builder_.add_model_file(path, options);
        } catch (const Error& e) {
            rethrow_with_message(e, say(language_, "{}", "не удалось прочитать модель: {}", e.what()));
        }
    }

    // The triangles so far against the limits, as each object is added: a file of many large meshes
    // stops at the one that goes over.
    void check_triangles() {
        scene_triangles_ += builder_.objects().back().indices.size() / 3;
        check_limit(&Limits::stored_triangles, scene_triangles_,
                    say(language_, "the meshes and polygons up to here", "модели и многоугольники до этой строки"), language_);
        if (repeat_) {
            const uint64_t copies = uint64_t(repeat_->columns) * repeat_->rows * repeat_->layers;
            check_limit(&Limits::triangles, copies * scene_triangles_,
                        say(language_, "the meshes and polygons up to here ({} triangles) repeated {}x{}x{}",
                            "модели и многоугольники до этой строки (треугольников: {}), повторённые {}x{}x{} раз",
                            scene_triangles_, repeat_->columns, repeat_->rows, repeat_->layers),
                        language_);
        }
    }

    std::filesystem::path file_, folder_;
    const ReadPolicy& policy_;
    Language language_;
    SceneBuilder builder_;
    std::vector<float> opacity_;  // per object added, in order
    uint64_t scene_triangles_ = 0;
    // Each mesh file read: the first object it made and how many (one an OBJ group).
    std::map<std::string, std::pair<std::size_t, std::size_t>> mesh_objects_;
    SceneFile result_;
    PendingObject object_;
    std::size_t camera_line_ = 0;
};

}  // namespace

LightSpec parse_light_spec(std::string_view text, Language language) {
    auto fail = [&](const std::string& problem) -> Error {
        return Error(say(language, "light '{}': {} (expected e.g. point:1,2,3 or dir:0,0,1,intensity=0.8,color=1/0.9/0.8)",
                         "источник света «{}»: {} (пример: point:1,2,3 или dir:0,0,1,intensity=0.8,color=1/0.9/0.8)",
                         printable(text), problem));
    };
    std::size_t colon = text.find(':');
    if (colon == std::string_view::npos) throw fail(say(language, "missing ':' after the light type", "после типа источника нет «:»"));
    std::string type = lower(std::string(text.substr(0, colon)));
    LightSpec light;
    if (type == "point") light.type = HSR_LIGHT_POINT;
    else if (type == "dir" || type == "directional") light.type = HSR_LIGHT_DIRECTIONAL;
    else throw fail(say(language, "unknown light type '{}' (point or dir)",
                        "неизвестный тип источника «{}» (point или dir)", printable(type)));

    std::vector<std::string_view> parts = split(text.substr(colon + 1), ',');
    if (parts.size() < 3) throw fail(say(language, "needs three coordinates x,y,z", "нужны три координаты x,y,z"));
    for (int k = 0; k < 3; ++k) {
        std::optional<float> v = to_float(parts[static_cast<std::size_t>(k)]);
        if (!v)
            throw fail(say(language, "coordinate '{}' is not a finite number", "координата «{}» не является конечным числом",
                           printable(parts[static_cast<std::size_t>(k)])));
        light.vector[k] = *v;
    }
    bool seen_intensity = false, seen_color = false, seen_space = false;
    for (std::size_t i = 3; i < parts.size(); ++i) {
        std::size_t equals = parts[i].find('=');
        if (equals == std::string_view::npos) throw fail(say(language, "'{}' is not key=value",
                                                             "«{}» — не пара ключ=значение", printable(parts[i])));
        std::string key = lower(std::string(parts[i].substr(0, equals)));
        std::string_view value = parts[i].substr(equals + 1);
        if (key == "intensity") {
            std::optional<float> v = to_float(value);
            if (!v || *v < 0.0f)
                throw fail(say(language, "intensity '{}' is not a number >= 0", "интенсивность «{}» — не число >= 0", printable(value)));
            if (seen_intensity) throw fail(say(language, "intensity given twice", "интенсивность задана дважды"));
            seen_intensity = true;
            light.intensity = *v;
        } else if (key == "color" || key == "colour") {
            std::optional<glm::vec3> c = parse_color_text(value);
            if (!c)
                throw fail(say(language, "colour '{}' is not r/g/b in [0, 1] or #rrggbb", "цвет «{}» — ни r/g/b из [0, 1], ни #rrggbb",
                               printable(value)));
            if (seen_color) throw fail(say(language, "colour given twice", "цвет задан дважды"));
            seen_color = true;
            light.color = *c;
        } else if (key == "space") {
            if (value != "camera" && value != "world")
                throw fail(say(language, "space '{}' is not camera or world", "space «{}» — ни camera, ни world", printable(value)));
            if (seen_space) throw fail(say(language, "space given twice", "space задано дважды"));
            seen_space = true;
            light.camera_space = value == "camera";
        } else {
            throw fail(say(language, "unknown key '{}' (intensity, color, space)", "неизвестный ключ «{}» (есть intensity, color, space)",
                           printable(key)));
        }
    }
    if (light.type == HSR_LIGHT_DIRECTIONAL) {
        const float length = glm::length(light.vector);
        if (length > 0.0f && std::isfinite(length)) {
            light.vector /= length;
        } else {  // the length overflows or underflows a float (dir:3e38,3e38,3e38): in double
            const glm::dvec3 direction(light.vector);
            const double exact = glm::length(direction);
            if (!(exact > 0.0)) throw fail(say(language, "a direction cannot be zero", "направление не может быть нулевым"));
            light.vector = glm::vec3(direction / exact);
        }
    }
    return light;
}

bool is_scene_file(const std::filesystem::path& file) { return lower(file.extension().string()) == ".scene"; }

SceneFile load_scene_file(const std::filesystem::path& file, const ReadPolicy& policy, Language language) {
    return SceneParser(file, policy, language).parse();
}

}  // namespace hsr
