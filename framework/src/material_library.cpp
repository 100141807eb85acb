// OBJ material libraries: the MTL format of Wavefront's Advanced Visualizer (the "MTL" appendix of
// its manual, as in Paul Bourke's copy, paulbourke.net/dataformats/mtl/). Only what hsr draws is
// read: each material's diffuse colour, Kd. The file named by an OBJ file is opened only inside the
// OBJ file's folder and only when it is a regular file: a model from elsewhere could otherwise make
// hsr read /etc/passwd's neighbours, or wait forever on a named pipe.
#include "material_library.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hsr {
namespace {

bool is_space(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

std::vector<std::string_view> words_of(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

bool parse_float(std::string_view word, float& value) {
    if (word.starts_with('+')) word.remove_prefix(1);
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    return ec == std::errc() && end == word.data() + word.size() && std::isfinite(value);
}

// Closes a file descriptor when it goes out of scope.
struct Descriptor {
    int fd = -1;
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

MaterialLibrary parse_material_library(std::string_view text, const std::string& what,
                                       std::vector<std::string>& warnings) {
    MaterialLibrary library;
    std::string current;
    bool have_current = false, clamped = false;
    std::size_t bad_colors = 0, line_number = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_number;
        line = line.substr(0, line.find('#'));
        const std::vector<std::string_view> words = words_of(line);
        if (words.empty()) continue;
        if (words[0] == "newmtl") {
            have_current = words.size() >= 2;
            if (have_current) current = std::string(words[1]);
        } else if (words[0] == "Kd" && have_current) {
            glm::vec3 color;
            bool ok = words.size() == 2 || words.size() == 4;  // one value is grey
            for (int k = 0; ok && k < 3; ++k) ok = parse_float(words[words.size() == 2 ? 1 : 1 + k], color[k]);
            if (!ok) {
                ++bad_colors;
                continue;
            }
            const glm::vec3 inside = glm::clamp(color, glm::vec3(0.0f), glm::vec3(1.0f));
            clamped = clamped || inside != color;
            library.diffuse[current] = inside;
        } else if (words[0].starts_with("map_")) {
            library.has_textures = true;
        }
    }
    if (bad_colors > 0)
        warnings.push_back(fmt::format("{}: {} Kd line{} not read (expected Kd r g b, three numbers)", what, bad_colors,
                                       bad_colors == 1 ? "" : "s"));
    if (clamped) warnings.push_back(fmt::format("{}: Kd values outside [0, 1] clamped to it", what));
    return library;
}

bool read_material_file(const std::filesystem::path& model, const std::string& name, std::string& text,
                        std::vector<std::string>& warnings) {
    namespace fs = std::filesystem;
    const std::string shown = printable(name, kMaxQuotedPathChars);
    const std::string model_shown = printable(model.string(), kMaxQuotedPathChars);
    auto refuse = [&](const std::string& why) {
        warnings.push_back(fmt::format("{}: material library '{}' not read: {}", model_shown, shown, why));
        return false;
    };
    const fs::path relative(name);
    if (name.empty() || relative.is_absolute() || relative.has_root_name() || relative.has_root_directory())
        return refuse("only a file in the model's folder is read");
    for (const fs::path& part : relative)
        if (part == "..") return refuse("only a file in the model's folder is read");
    std::error_code ec;
    const fs::path folder = fs::canonical(fs::absolute(model, ec).parent_path(), ec);
    if (ec) return refuse("the model's folder cannot be resolved");
    const fs::path resolved = fs::canonical(folder / relative, ec);
    if (ec) return refuse("no such file");
    const fs::path inside = resolved.lexically_relative(folder);
    if (inside.empty() || *inside.begin() == ".." || inside == ".")
        return refuse("it leads out of the model's folder");
    // The path checked is the one opened: every link in it is resolved, and O_NOFOLLOW refuses a
    // link put in its place since; O_NONBLOCK keeps a pipe from holding the open.
    Descriptor file{::open(resolved.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK)};
    if (file.fd < 0) return refuse(std::generic_category().message(errno));
    struct stat info {};
    if (::fstat(file.fd, &info) != 0 || !S_ISREG(info.st_mode))
        return refuse("not a regular file (a pipe, device or socket)");
    check_limit(&Limits::model_bytes, static_cast<uint64_t>(info.st_size), shown);
    text.assign(static_cast<std::size_t>(info.st_size), '\0');
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t got = ::read(file.fd, text.data() + done, text.size() - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) return refuse(std::generic_category().message(errno));
        if (got == 0) break;  // the file shrank meanwhile
        done += static_cast<std::size_t>(got);
    }
    text.resize(done);
    return true;
}

}  // namespace hsr
