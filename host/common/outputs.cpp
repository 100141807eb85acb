// Output paths, checked before a command starts its work (commands.hpp).
#include "common/options.hpp"
#include "common/outputs.hpp"

#include "hsr/atomic_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <system_error>
#include <unordered_map>

namespace fs = std::filesystem;

namespace {

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

std::string joined(const std::vector<std::string>& items, const char* last_separator) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += i + 1 == items.size() ? last_separator : ", ";
        out += items[i];
    }
    return out;
}

}  // namespace

std::vector<fs::path> hsr::host::check_outputs(const std::vector<OutputFile>& outputs) {
    std::unordered_map<std::string, const OutputFile*> seen;
    std::vector<fs::path> resolved_paths;
    for (const OutputFile& out : outputs) {
        const std::string name = hsr::printable(out.path.string(), hsr::kMaxQuotedPathChars);  // as messages quote it
        if (name.empty()) throw UsageError("--{}: no file name given", out.option);
        std::error_code ec;
        const fs::file_status status = fs::status(out.path, ec);
        if (fs::is_directory(status)) throw hsr::Error("--{} '{}': is a folder, not a file", out.option, name);
        if (!out.extensions.empty()) {
            const std::string extension = lowercase(out.path.extension().string());
            if (std::find(out.extensions.begin(), out.extensions.end(), extension) == out.extensions.end())
                throw UsageError("--{} '{}': the name must end in {} (the format written)", out.option, name,
                                 joined(out.extensions, " or "));
        }
        // The file is written as a temporary in the folder of the file it replaces (a link is followed),
        // unless it is a device or a pipe, which is written in place (hsr/atomic_file.hpp).
        const fs::path destination = hsr::AtomicFile::destination(out.path);
        const fs::path folder = destination.has_parent_path() ? destination.parent_path() : fs::path(".");
        const bool in_place = fs::exists(status) && !fs::is_regular_file(status);
        if (!in_place && !fs::is_directory(folder, ec))
            throw hsr::Error("--{} '{}': the folder '{}' does not exist", out.option, name,
                             hsr::printable(folder.string(), hsr::kMaxQuotedPathChars));
        if ((fs::exists(status) && ::access(destination.c_str(), W_OK) != 0) ||
            (!in_place && ::access(folder.c_str(), W_OK) != 0))
            throw hsr::Error("--{} '{}': cannot write there (permission denied)", out.option, name);

        const fs::path resolved = fs::weakly_canonical(fs::absolute(out.path, ec), ec);
        const auto [other, inserted] = seen.emplace(resolved.string(), &out);
        if (!inserted)
            throw UsageError("--{} and --{} name the same file '{}'", other->second->option, out.option, name);
        resolved_paths.push_back(resolved);
    }
    return resolved_paths;
}
