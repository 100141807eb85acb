// hsr view's frame requests (view_request.hpp): each field read with its type checked, then checked
// with the same rules and messages as the matching option of hsr render.
#include "view/server/view_request.hpp"

#include "common/options.hpp"

#include "hsr/limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

using nlohmann::json;

namespace {

using hsr::host::ViewError;

// A request field that is present and not null, or nullptr.
const json* member(const json& object, const char* name) {
    const auto it = object.find(name);
    return it == object.end() || it->is_null() ? nullptr : &*it;
}

std::string text_field(const json& object, const char* name, const std::string& field, std::string fallback) {
    const json* value = member(object, name);
    if (value == nullptr) return fallback;
    if (!value->is_string()) throw ViewError(400, field, fmt::format("{}: expected a string", field));
    return value->get<std::string>();
}

double number_field(const json& object, const char* name, const std::string& field, double fallback) {
    const json* value = member(object, name);
    if (value == nullptr) return fallback;
    if (!value->is_number()) throw ViewError(400, field, fmt::format("{}: expected a number", field));
    return value->get<double>();
}

// Parameter values are strings as on the command line; a number or a boolean is taken as its text.
std::vector<hsr::Setting> settings_field(const json& object, const char* name) {
    std::vector<hsr::Setting> settings;
    const json* value = member(object, name);
    if (value == nullptr) return settings;
    if (!value->is_object()) throw ViewError(400, name, fmt::format("{}: expected an object of name: value", name));
    for (const auto& [key, v] : value->items()) {
        if (v.is_string())
            settings.emplace_back(key, v.get<std::string>());
        else if (v.is_boolean() || v.is_number())
            settings.emplace_back(key, v.dump());
        else
            throw ViewError(400, fmt::format("{}.{}", name, key), fmt::format("{}.{}: expected a string", name, key));
    }
    return settings;
}

glm::vec3 vector_field(const json& camera, const char* name) {
    const json* value = member(camera, name);
    const std::string field = fmt::format("camera.{}", name);
    const std::string expected = fmt::format("{}: expected three numbers, as [x, y, z] or \"x,y,z\"", field);
    std::string text;
    if (value->is_array()) {
        for (std::size_t k = 0; k < value->size(); ++k) {
            const json& item = (*value)[k];
            if (!item.is_number()) throw ViewError(400, field, expected);
            if (k > 0) text += ',';
            text += fmt::format("{}", item.get<double>());
        }
    } else if (value->is_string()) {
        text = value->get<std::string>();
    } else {
        throw ViewError(400, field, expected);
    }
    try {
        return hsr::host::parse_vector_option(text, name);
    } catch (const hsr::Error& e) {
        throw ViewError(400, field, e.what());
    }
}

constexpr std::size_t kMaxBufferSpecs = 4;

// {"names": [...], "region": [x, y, width, height]}, each optional: every buffer, the whole picture.
hsr::host::BufferSpec buffer_spec(const json& spec) {
    const char* shape = "buffers: expected {\"names\": [...], \"region\": [x, y, width, height]}";
    if (!spec.is_object()) throw ViewError(400, "buffers", shape);
    for (const auto& [key, value] : spec.items())
        if (key != "names" && key != "region")
            throw ViewError(400, "buffers", fmt::format("buffers: no field '{}' ({})", hsr::printable(key), shape));
    hsr::host::BufferSpec out;
    if (const json* names = member(spec, "names")) {
        if (!names->is_array()) throw ViewError(400, "buffers.names", "buffers.names: expected a list of buffer names");
        for (const json& name : *names) {
            const auto known = std::find_if(std::begin(hsr::host::kBufferNames), std::end(hsr::host::kBufferNames),
                                            [&](const char* n) { return name.is_string() && name.get<std::string>() == n; });
            if (known == std::end(hsr::host::kBufferNames))
                throw ViewError(400, "buffers.names",
                                fmt::format("buffers.names: {} is not a buffer (depth, face, instance, object, "
                                            "depth_tests, depth_complexity, scene_z)", hsr::printable(name.dump(), 40)));
            if (std::find(out.names.begin(), out.names.end(), *known) == out.names.end()) out.names.push_back(*known);
        }
    } else {
        out.names.assign(std::begin(hsr::host::kBufferNames), std::end(hsr::host::kBufferNames));
    }
    if (const json* region = member(spec, "region")) {
        const bool whole_numbers = region->is_array() && region->size() == 4 &&
                                   std::all_of(region->begin(), region->end(), [](const json& v) {
                                       return v.is_number_unsigned() && v.get<uint64_t>() <= hsr::host::view_max_image_side;
                                   });
        if (!whole_numbers || (*region)[2].get<uint32_t>() == 0 || (*region)[3].get<uint32_t>() == 0)
            throw ViewError(400, "buffers.region",
                            fmt::format("buffers.region: expected [x, y, width, height], whole numbers up to {}, width "
                                        "and height at least 1", hsr::host::view_max_image_side));
        out.region = std::array<uint32_t, 4>{(*region)[0].get<uint32_t>(), (*region)[1].get<uint32_t>(),
                                             (*region)[2].get<uint32_t>(), (*region)[3].get<uint32_t>()};
    }
    return out;
}

}  // namespace

bool hsr::host::FrameRequest::wants(const char* buffer) const {
    for (const BufferSpec& spec : buffers)
        if (std::find(spec.names.begin(), spec.names.end(), buffer) != spec.names.end()) return true;
    return false;
}

hsr::host::FrameRequest hsr::host::parse_frame_request(const json& r) {
    if (!r.is_object()) throw ViewError(400, "", "the request must be a JSON object");
    FrameRequest q;
    q.model = text_field(r, "model", "model", "");
    if (q.model.empty()) throw ViewError(400, "model", "no model given");
    q.algorithm = text_field(r, "algorithm", "algorithm", default_algorithm);
    q.lighting = text_field(r, "lighting", "lighting", default_lighting);
    q.params = settings_field(r, "params");
    q.lighting_params = settings_field(r, "lighting_params");

    const double width = number_field(r, "width", "width", 512), height = number_field(r, "height", "height", 512);
    if (!(width >= 1 && height >= 1 && width <= view_max_image_side &&
          height <= view_max_image_side) || width != std::floor(width) || height != std::floor(height))
        throw ViewError(400, "width", fmt::format("image size {}x{}: each side must be between 1 and {}", width, height,
                                                  view_max_image_side));
    q.width = uint32_t(width);
    q.height = uint32_t(height);
    try {
        hsr::check_limit(&hsr::Limits::image_pixels, uint64_t(q.width) * q.height,
                         fmt::format("image size {}x{}", q.width, q.height));
    } catch (const hsr::Error& e) {
        throw ViewError(400, "width", e.what());
    }

    static const json no_camera = json::object();
    const json* camera_value = member(r, "camera");
    if (camera_value != nullptr && !camera_value->is_object())
        throw ViewError(400, "camera", "camera: expected an object");
    const json& camera = camera_value ? *camera_value : no_camera;
    hsr::CameraSettings& v = q.view;
    v.width = q.width;
    v.height = q.height;
    v.yaw_degrees = float(number_field(camera, "yaw", "camera.yaw", 0));
    v.pitch_degrees = float(number_field(camera, "pitch", "camera.pitch", 0));
    v.zoom = float(number_field(camera, "zoom", "camera.zoom", 1));
    v.fov_y_degrees = float(number_field(camera, "fov", "camera.fov", 35));
    for (const auto& [name, value] : {std::pair{"yaw", v.yaw_degrees}, {"pitch", v.pitch_degrees}, {"zoom", v.zoom}})
        if (!std::isfinite(value)) throw ViewError(400, fmt::format("camera.{}", name), fmt::format("--{} must be a finite number", name));
    if (!(v.zoom > 0)) throw ViewError(400, "camera.zoom", "--zoom must be positive");
    if (!(v.fov_y_degrees > 0 && v.fov_y_degrees < 180))
        throw ViewError(400, "camera.fov", "--fov must be between 0 and 180 degrees");
    const std::string projection = text_field(camera, "projection", "camera.projection", "perspective");
    if (projection != "perspective" && projection != "orthographic")
        throw ViewError(400, "camera.projection", fmt::format("camera.projection '{}': expected 'perspective' or 'orthographic'",
                                                              hsr::printable(projection)));
    v.orthographic = projection == "orthographic";
    if (member(camera, "eye") != nullptr) {
        hsr::LookAt look_at;
        look_at.eye = vector_field(camera, "eye");
        if (member(camera, "target") != nullptr) look_at.target = vector_field(camera, "target");
        if (member(camera, "up") != nullptr) look_at.up = vector_field(camera, "up");
        v.look_at = look_at;
    } else {
        for (const char* name : {"target", "up"})
            if (member(camera, name) != nullptr)
                throw ViewError(400, fmt::format("camera.{}", name), fmt::format("--{} goes with --eye", name));
    }
    q.camera_key = fmt::format("{}x{} {}", q.width, q.height, camera.dump());

    if (const json* step = member(r, "step")) {
        if (!step->is_number() || step->get<double>() != std::floor(step->get<double>()))
            throw ViewError(400, "step", "step: expected a whole number (or null for the full render)");
        if (step->get<double>() < 1) throw ViewError(400, "step", fmt::format("--step {}: steps count from 1", step->dump()));
        q.step = step->get<double>() > 1e18 ? uint64_t(1e18) : step->get<uint64_t>();
    }
    q.language = text_field(r, "language", "language", "en");
    if (q.language != "en" && q.language != "ru")
        throw ViewError(400, "language", fmt::format("language '{}': expected 'en' or 'ru'", hsr::printable(q.language)));
    if (const json* buffers = member(r, "buffers")) {
        if (buffers->is_boolean()) {
            if (buffers->get<bool>()) q.buffers.push_back(buffer_spec(json::object()));
        } else if (buffers->is_object()) {
            q.buffers.push_back(buffer_spec(*buffers));
        } else if (buffers->is_array() && buffers->size() <= kMaxBufferSpecs) {
            for (const json& spec : *buffers) q.buffers.push_back(buffer_spec(spec));
            q.buffers_as_list = true;
        } else {
            throw ViewError(400, "buffers", fmt::format("buffers: expected true, false, {{\"names\": [...], \"region\": "
                                                        "[x, y, width, height]}} or a list of at most {} of those",
                                                        kMaxBufferSpecs));
        }
    }
    if (const json* picture = member(r, "picture")) {
        if (!picture->is_boolean()) throw ViewError(400, "picture", "picture: expected true or false");
        q.picture = picture->get<bool>();
    }
    const std::string edges = text_field(r, "edges", "edges", "features");
    if (edges != "features" && edges != "all")
        throw ViewError(400, "edges", fmt::format("--edges '{}': expected 'all' or 'features'", hsr::printable(edges)));
    q.edges = edges == "all" ? hsr::EdgeSelection::kAll : hsr::EdgeSelection::kFeatures;
    const std::string hidden = text_field(r, "hidden", "hidden", "hidden");
    if (hidden != "hidden" && hidden != "dashed")
        throw ViewError(400, "hidden", fmt::format("--hidden '{}': expected 'dashed' or 'hidden'", hsr::printable(hidden)));
    q.hidden = hidden == "dashed" ? hsr::HiddenLines::kDashed : hsr::HiddenLines::kHidden;
    return q;
}

void hsr::host::check_settings(const hsr::Plugin& plugin, const std::vector<hsr::Setting>& settings, const char* field) {
    for (const hsr::Setting& setting : settings) {
        try {
            hsr::resolve_params(plugin.descriptor, {setting});
        } catch (const hsr::Error& e) {
            throw ViewError(400, fmt::format("{}.{}", field, setting.first), e.what());
        }
    }
    try {
        hsr::resolve_params(plugin.descriptor, settings);
    } catch (const hsr::Error& e) {
        throw ViewError(400, field, e.what());
    }
}
