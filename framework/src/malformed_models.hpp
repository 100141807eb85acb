// Checks on model files before OpenMesh reads them. OpenMesh's readers trust their input: a PLY
// header without end_header or an OFF face claiming a billion corners makes them spin, and an
// unparsable number silently shifts every later vertex. These checks walk the text (structure,
// finite coordinates, index ranges) and throw hsr::Error "file:line: message" at the first problem.
// The checks of OBJ, OFF and PLY files also keep what they parse, which model_reader.cpp builds the
// mesh from.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

// A model file's vertex positions and faces. For OBJ, as OpenMesh's OBJ reader reads the text that
// obj_text_for_openmesh returns (same vertices in the same order, same numbers).
struct ModelContents {
    std::vector<std::array<float, 3>> positions;
    std::vector<int32_t> corners;     // each face's vertices as listed (0-based), face after face
    std::vector<uint32_t> face_ends;  // where each face's corners end
    // Colours the file gives, each channel in [0, 1]: one per position (OFF, PLY), or one per face
    // (OFF, PLY), a face without one NaN; empty when the file gives none.
    std::vector<std::array<float, 3>> vertex_colors, face_colors;
    // OBJ: the material libraries named (mtllib), and each usemtl line, from which face on.
    struct MaterialUse {
        uint32_t first_face;
        std::string name;
    };
    std::vector<std::string> material_libraries;
    std::vector<MaterialUse> material_uses;
    // OBJ: each o line (object) and g line (group), from which face on.
    struct Group {
        uint32_t first_face;
        std::string name;
        bool is_object;  // an o line
    };
    std::vector<Group> groups;
};

// Checks an OBJ file and returns what it holds: the same contents, or the same first error, as a
// check line by line, with pieces of about piece_bytes checked in parallel.
ModelContents check_obj_text(const std::filesystem::path& file, std::string_view text,
                           std::size_t piece_bytes = std::size_t(1) << 18);
// Checks an OBJ file and returns its text for OpenMesh's OBJ reader, with lines that would make it
// open other files commented out (the reference that tests compare check_obj_text with).
std::string obj_text_for_openmesh(const std::filesystem::path& file, std::string text);
// Checks an ASCII OFF file and returns what it holds.
ModelContents check_off_text(const std::filesystem::path& file, std::string_view text);
// Checks an ASCII or binary PLY file and returns what it holds.
ModelContents check_ply_text(const std::filesystem::path& file, std::string_view text);
void check_stl_text(const std::filesystem::path& file, std::string_view text);  // ASCII or binary

}  // namespace hsr
