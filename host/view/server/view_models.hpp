// The model files hsr view may open: those found in its model folders and those uploaded to it, each
// named by an id ("0/bunny.obj", "upload/3/part.stl"). Nothing else is ever opened: an id is looked
// up, never turned into a path by joining text.
#pragma once

#include "hsr/error.hpp"
#include "hsr/language.hpp"
#include "hsr/read_policy.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace hsr::host {

// An error of one request: its HTTP status, and the request field at fault when there is one.
struct ViewError : hsr::Error {
    ViewError(int status, std::string field, const std::string& message)
        : hsr::Error(message), status(status), field(std::move(field)) {}
    int status;
    std::string field;
};

struct ModelEntry {
    std::string id;
    std::string name;  // the file name
    std::filesystem::path path;
    uint64_t bytes = 0;
    bool scene = false;  // a .scene file
};

class ModelCatalog {
public:
    // Folders that do not exist are kept (their index stays theirs) but list nothing. Uploads go into
    // a fresh folder under upload_parent, hsr-view-uploads-<pid>-<random>, removed again by the
    // destructor; such folders left by servers that are gone (killed) are removed first.
    ModelCatalog(std::vector<std::filesystem::path> folders, const std::filesystem::path& upload_parent);
    ~ModelCatalog();
    ModelCatalog(const ModelCatalog&) = delete;
    ModelCatalog& operator=(const ModelCatalog&) = delete;

    const std::vector<std::filesystem::path>& folders() const { return folders_; }
    const std::filesystem::path& upload_folder() const { return upload_dir_; }
    // Every model file of the folders (found again on each call: .obj .off .ply .stl .gltf .glb .scene, at
    // most 3 folders deep, hidden files and folders skipped, links that leave their folder skipped)
    // and the uploads, sorted by id.
    std::vector<ModelEntry> list() const;
    // The entry of an id; ViewError 404 "no model '<id>'" for anything list() would not give.
    // `language`: of the messages here and below (the scene editor's requests carry the page's).
    ModelEntry find(const std::string& id, hsr::Language language = hsr::Language::english) const;
    // Stores an upload and returns its id; ViewError 400 for a name that is not a model file's.
    // An upload whose id is `replaces` goes (the scene editor sends each edit this way, so its
    // edits do not push other uploads out). A .scene upload's relative mesh paths are taken
    // relative to the folder of the served .scene model `base_model`, if one is named (the scene
    // it was edited from). The caller has checked the size against the upload-bytes limit.
    std::string add_upload(const std::string& file_name, const std::string& bytes, const std::string& replaces = "",
                           const std::string& base_model = "", hsr::Language language = hsr::Language::english);
    // The text of a .scene model; ViewError 400 for any other kind, 404 for an unknown id.
    std::string scene_text(const std::string& id, uint64_t max_bytes, hsr::Language language = hsr::Language::english) const;

    // What a model of the catalog may read: files inside the folders and the uploads, links
    // resolved as far as the path exists (a .scene file's meshes, say).
    hsr::ReadPolicy read_policy() const;
    // The folders of read_policy(): those served, then the uploads'.
    std::vector<std::filesystem::path> read_folders() const;

private:
    std::vector<std::filesystem::path> folders_;
    std::filesystem::path upload_dir_;
    mutable std::mutex uploads_mutex_;
    std::map<std::string, ModelEntry> uploads_;
    uint64_t next_upload_ = 1;
};

// What a model of hsr view may read: files inside these folders, links resolved as far as the path
// exists.
hsr::ReadPolicy served_read_policy(std::vector<std::filesystem::path> folders);

// The model file extensions hsr view lists: ".obj", ".off", ".ply", ".stl", ".gltf", ".glb", ".scene".
bool is_model_file_name(const std::string& name);

}  // namespace hsr::host
