// The .scene reader's messages in Russian (hsr view's page in Russian shows them in its scene
// editor): broken scenes, one mistake each, read in both languages. The Russian message must name
// the line at fault as the English one does ("file:line: "), be written in Cyrillic and say what is
// wrong in the words written here; the English message must be exactly the one written here, as
// the command line has always printed it.
#include "hsr/error.hpp"
#include "hsr/language.hpp"
#include "hsr/scene_file.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        std::random_device rd;
        path = fs::temp_directory_path() / ("hsr-test-scene-ru-" + std::to_string(rd()) + "-" + std::to_string(counter++));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    fs::path write(const std::string& name, const std::string& content) const {
        const fs::path file = path / name;
        std::ofstream(file, std::ios::binary) << content;
        return file;
    }
};

// Whether the UTF-8 text holds a letter of the Cyrillic block U+0400..U+04FF.
bool has_cyrillic(const std::string& text) {
    for (std::size_t i = 0; i + 1 < text.size(); ++i) {
        const auto lead = static_cast<unsigned char>(text[i]), next = static_cast<unsigned char>(text[i + 1]);
        if (lead >= 0xD0 && lead <= 0xD3 && next >= 0x80 && next <= 0xBF) return true;
    }
    return false;
}

// The message of reading `file`, which must fail; Language::english goes through the default
// argument, as the command line reads a scene.
std::string message_of(const fs::path& file, std::optional<hsr::Language> language) {
    try {
        if (language)
            hsr::load_scene_file(file, {}, *language);
        else
            hsr::load_scene_file(file);
    } catch (const hsr::Error& e) {
        return e.what();
    }
    FAIL("the scene was read without an error: " << file.string());
    return {};
}

const std::string triangle = "polygon\n"
                             "color 1 0 0\n"
                             "vertex 0 0 0\n"
                             "vertex 1 0 0\n"
                             "vertex 0 1 0\n";  // lines 1-5

struct Case {
    std::string scene;
    std::size_t line;     // 0: the message names no line
    std::string english;  // after "file:line: "
    std::string russian;  // a part of the Russian message, after "file:line: "
};

}  // namespace

TEST_CASE("scene errors in Russian name the line and say what is wrong", "[scene][language]") {
    TempDir dir;
    std::ofstream(dir.path / "model.xyz") << "not a model\n";
    const std::string missing = (dir.path / "nothere.obj").lexically_normal().string();
    const std::string unknown_format = (dir.path / "model.xyz").lexically_normal().string();
    const std::vector<Case> cases = {
        {triangle + "lihgt point:1,2,3\n", 6, "unknown statement 'lihgt'", "неизвестная инструкция «lihgt»"},
        {"background 1 1\n" + triangle, 1, "expected: background <r> <g> <b>  (each in [0, 1])", "ожидалось: background <r> <g> <b>"},
        {"polygon\ncolor 2 0 0\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n", 2, "colour channel 2 is outside [0, 1]",
         "компонента цвета 2 вне отрезка [0, 1]"},
        {triangle + "light point:1,2\n", 6,
         "light 'point:1,2': needs three coordinates x,y,z (expected e.g. point:1,2,3 or dir:0,0,1,intensity=0.8,color=1/0.9/0.8)",
         "источник света «point:1,2»: нужны три координаты x,y,z"},
        {triangle + "light spot:1,2,3\n", 6,
         "light 'spot:1,2,3': unknown light type 'spot' (point or dir) (expected e.g. point:1,2,3 or "
         "dir:0,0,1,intensity=0.8,color=1/0.9/0.8)",
         "неизвестный тип источника «spot» (point или dir)"},
        {triangle + "rotate 30 0 0 0\n", 6, "the rotation axis is zero", "ось поворота нулевая"},
        {triangle + "translate 1 x 2\n", 6, "offset 'x' is not a finite number", "сдвиг: «x» не является конечным числом"},
        {triangle + "camera orbit yaw\n", 6, "camera setting 'yaw' needs a value", "параметру камеры «yaw» нужно значение"},
        {triangle + "camera orbit\ncamera orbit zoom 2\n", 7, "the camera is already set on line 6", "камера уже задана в строке 6"},
        {triangle + "clip-plane 0 0 0 1\n", 6, "the clip plane's normal (a, b, c) is zero", "нормаль плоскости отсечения (a, b, c) нулевая"},
        {triangle + "repeat 2 2\n", 6, "expected: repeat <columns> <rows> <layers> [gap <g>] [jitter <degrees>]",
         "ожидалось: repeat <столбцы> <ряды> <слои>"},
        {triangle + "opacity 2\n", 6, "opacity must be within [0, 1]", "непрозрачность должна быть из [0, 1]"},
        {"vertex 0 0 0\n" + triangle, 1, "'vertex' must follow a mesh or polygon line", "«vertex» должна стоять после строки mesh или polygon"},
        {triangle + "name \"open quote\n", 6, "unterminated quote", "кавычка не закрыта"},
        {"# a comment\npolygon\nvertex 0 0 0\nvertex 1 0 0\n", 2, "the polygon has 2 vertex lines; it needs at least 3",
         "строк vertex у многоугольника: 2, а нужно не меньше трёх"},
        {"polygon\nvertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\n", 1, "polygon 1: has no area (its vertices are collinear)",
         "многоугольник 1: площадь равна нулю (вершины лежат на одной прямой)"},
        {triangle + "mesh nothere.obj\n", 6, missing + ": no such file", missing + ": нет такого файла"},
        {triangle + "mesh model.xyz\n", 6,
         unknown_format + ": unsupported model format '.xyz' (hsr reads .obj, .off, .ply, .stl, .gltf and .glb; convert others "
                          "to .glb with assimp: see docs/formats.md)",
         "не удалось прочитать модель: " + unknown_format + ": unsupported model format '.xyz'"},
        {triangle + "crease 30\n", 6, "crease applies to meshes only", "crease относится только к моделям (mesh)"},
        {triangle + "samples 3\n", 6, "samples '3': expected 1, 2, 4, 8 or 16", "samples «3»: ожидалось 1, 2, 4, 8 или 16"},
        {"# nothing but a comment\n", 0, "the scene has no mesh or polygon", "в сцене нет ни модели (mesh), ни многоугольника (polygon)"},
    };
    for (std::size_t c = 0; c < cases.size(); ++c) {
        const Case& test = cases[c];
        const fs::path file = dir.write(fmt::format("case-{}.scene", c), test.scene);
        const std::string where = test.line ? fmt::format("{}:{}: ", file.string(), test.line) : file.string() + ": ";
        INFO("case " << c << ":\n" << test.scene);
        const std::string english = message_of(file, std::nullopt);
        CHECK(english == where + test.english);
        CHECK(message_of(file, hsr::Language::english) == english);
        const std::string russian = message_of(file, hsr::Language::russian);
        INFO("Russian: " << russian);
        CHECK(russian.rfind(where, 0) == 0);
        CHECK(has_cyrillic(russian.substr(where.size())));
        CHECK(russian.find(test.russian, where.size()) != std::string::npos);
        CHECK(russian != english);
    }
}

TEST_CASE("light specifications in Russian, English by default", "[scene][language]") {
    for (const char* spec : {"point:1,2", "dir:0,0,0", "point:1,2,3,intensity=-1", "point:1,2,3,space=moon", "point:1,2,3,hue=3"}) {
        INFO(spec);
        std::string english, russian;
        try {
            hsr::parse_light_spec(spec);
        } catch (const hsr::Error& e) {
            english = e.what();
        }
        try {
            hsr::parse_light_spec(spec, hsr::Language::russian);
        } catch (const hsr::Error& e) {
            russian = e.what();
        }
        CHECK(english.rfind(fmt::format("light '{}': ", spec), 0) == 0);
        CHECK(!has_cyrillic(english));
        const std::string prefix = fmt::format("источник света «{}»: ", spec);
        CHECK(russian.rfind(prefix, 0) == 0);
        CHECK(has_cyrillic(russian.substr(std::min(prefix.size(), russian.size()))));
    }
}
