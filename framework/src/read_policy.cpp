// Which files loading may read (read_policy.hpp).
#include "hsr/read_policy.hpp"

#include <system_error>
#include <utility>

namespace fs = std::filesystem;

namespace hsr {

ReadPolicy::ReadPolicy(std::vector<fs::path> folders, std::string description)
    : restricted_(true), folders_(std::move(folders)), description_(std::move(description)) {}

bool ReadPolicy::allows(const fs::path& file) const {
    if (!restricted_) return true;
    std::error_code ec;
    // Links resolved as far as the path exists, so that a missing file inside is the reader's to report.
    const fs::path target = fs::weakly_canonical(fs::absolute(file, ec), ec);
    if (ec) return false;
    for (const fs::path& folder : folders_) {
        const fs::path root = fs::canonical(folder, ec);
        if (!ec && is_within(target, root)) return true;
        ec.clear();
    }
    return false;
}

bool is_within(const fs::path& inside, const fs::path& folder) {
    auto f = folder.begin(), i = inside.begin();
    for (; f != folder.end(); ++f, ++i)
        if (i == inside.end() || *i != *f) return false;
    return true;
}

}  // namespace hsr
