// OBJ material libraries (.mtl files): the diffuse colour (Kd) of each material, read only from
// the model's own folder (material_library.cpp).
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

struct MaterialLibrary {
    std::map<std::string, glm::vec3> diffuse;  // by material name: Kd, each channel clamped to [0, 1]
    bool has_textures = false;                 // a map_Kd (or other map_) line, which hsr does not sample
};

// The materials of an MTL text; `what` names the file in warnings. Lines other than newmtl, Kd
// and map_* are ignored; a Kd that is not three finite numbers (or one, for grey) leaves the
// material without a colour, with a warning. Appends one line per problem to `warnings`.
MaterialLibrary parse_material_library(std::string_view text, const std::string& what,
                                       std::vector<std::string>& warnings);

// The text of the material library `name` (as an OBJ mtllib line gives it) beside `model`, or a
// warning line (appended to `warnings`) and nothing. The name must be a relative path inside the
// model's folder, also once every link is followed, and a regular file; it is opened without
// following a last link and without waiting on a pipe, checked again through the open descriptor,
// and read against the model-bytes limit (hsr::LimitError over it).
bool read_material_file(const std::filesystem::path& model, const std::string& name, std::string& text,
                        std::vector<std::string>& warnings);

}  // namespace hsr
