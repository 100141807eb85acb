// Checks on model files before OpenMesh reads them. OpenMesh's readers trust their input: a PLY
// header without end_header or an OFF face claiming a billion corners makes them spin, and an
// unparsable number silently shifts every later vertex. These checks walk the text (structure,
// finite coordinates, index ranges) and throw hsr::Error "file:line: message" at the first problem.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace hsr {

// Returns the text for OpenMesh's OBJ reader, with lines that would make it open other files
// commented out.
std::string check_obj_text(const std::filesystem::path& file, std::string text);
// Returns the text re-written for OpenMesh's OFF reader, which accepts neither comment lines nor
// the counts on the header line, and reads a face's colour as the next face.
std::string check_off_text(const std::filesystem::path& file, std::string_view text);
// Returns the vertex positions and faces of an ASCII or binary PLY as a binary PLY of the one layout
// that OpenMesh's binary reader reads reliably.
std::string check_ply_text(const std::filesystem::path& file, std::string_view text);
void check_stl_text(const std::filesystem::path& file, std::string_view text);  // ASCII or binary

}  // namespace hsr
