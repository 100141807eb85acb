// Output paths, checked before a command starts its work.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hsr::host {

// A file a command will write, named by the option that gave it. Extensions: what its name may end
// with (".png"), any when empty.
struct OutputFile {
    std::string option;
    std::filesystem::path path;
    std::vector<std::string> extensions;
};

// Checked before any work, so that a mistyped path does not cost a long render or a whole benchmark:
// each name ends in one of its extensions (any case), is not a folder, lies in a folder that exists
// and can be written (where the file is made: hsr/atomic_file.hpp; for a symbolic link, the folder
// of the file it names), the file itself can be written if it exists, and no two outputs are the
// same file. Throws UsageError for a wrong name, hsr::Error for a folder or file that cannot be
// written. Nothing is created. Returns each output's absolute path, links in it resolved.
std::vector<std::filesystem::path> check_outputs(const std::vector<OutputFile>& outputs);

}  // namespace hsr::host
