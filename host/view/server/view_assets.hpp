// The files `hsr view` serves from inside the binary: the page (host/view/web/*, named
// "web/<file>") and the algorithm pages (docs/algorithms/*.md, named "algorithms/<file>"), turned
// into arrays at build time by cmake/embed_files.cmake.
#pragma once

#include <cstddef>
#include <string_view>

namespace hsr::host {

struct EmbeddedFile {
    const char* name;
    const unsigned char* bytes;
    std::size_t size;
};

extern const EmbeddedFile embedded_files[];
extern const std::size_t embedded_file_count;

// The file of that name, or nullptr.
const EmbeddedFile* find_embedded_file(std::string_view name);

}  // namespace hsr::host
