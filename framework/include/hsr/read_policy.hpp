// Which files loading a scene may read: any file (hsr render's model is the user's own choice), or
// only those inside given folders (hsr view, which serves its folders to a browser: a .scene file
// there must not reach a mesh elsewhere).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hsr {

class ReadPolicy {
public:
    // Any file.
    ReadPolicy() = default;
    // Only files inside these folders (or below them), links resolved; `description` names them
    // in a refusal: "mesh 'x' lies outside <description>".
    ReadPolicy(std::vector<std::filesystem::path> folders, std::string description);

    bool allows(const std::filesystem::path& file) const;
    bool restricted() const { return restricted_; }
    const std::string& description() const { return description_; }

private:
    bool restricted_ = false;
    std::vector<std::filesystem::path> folders_;
    std::string description_;
};

// Whether `inside` is `folder` or below it; both canonical.
bool is_within(const std::filesystem::path& inside, const std::filesystem::path& folder);

}  // namespace hsr
