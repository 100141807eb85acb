// hsr view's model files: the folders' listing and the uploads (view_models.hpp).
#include "view/server/view_models.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>

namespace fs = std::filesystem;

namespace {

constexpr int max_depth = 3;           // folders below a model folder that are searched
constexpr std::size_t max_uploads = 32;  // kept at once; the oldest goes first
constexpr std::string_view upload_prefix = "hsr-view-uploads-";

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

bool is_hidden(const fs::path& path) {
    const std::string name = path.filename().string();
    return !name.empty() && name[0] == '.';
}


void list_folder(std::size_t index, const fs::path& folder, std::vector<hsr::host::ModelEntry>& out) {
    std::error_code ec;
    const fs::path root = fs::canonical(folder, ec);
    if (ec || !fs::is_directory(root, ec)) return;
    fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        const fs::directory_entry& entry = *it;
        if (is_hidden(entry.path())) {
            if (entry.is_directory(ec)) it.disable_recursion_pending();
            continue;
        }
        if (entry.is_directory(ec)) {
            if (it.depth() + 1 >= max_depth) it.disable_recursion_pending();
            continue;
        }
        const std::string name = entry.path().filename().string();
        if (!hsr::host::is_model_file_name(name)) continue;
        // A link must stay inside the folder; so must the file it names.
        const fs::path target = fs::canonical(entry.path(), ec);
        if (ec || !hsr::is_within(target, root) || !fs::is_regular_file(target, ec)) {
            ec.clear();
            continue;
        }
        hsr::host::ModelEntry model;
        model.id = fmt::format("{}/{}", index, entry.path().lexically_relative(root).generic_string());
        model.name = name;
        model.path = target;
        model.bytes = fs::file_size(target, ec);
        model.scene = lowercase(entry.path().extension().string()) == ".scene";
        if (!ec) out.push_back(std::move(model));
        ec.clear();
    }
}

// Removes the upload folders of this user's servers whose process is gone: a server killed with
// SIGKILL cannot remove its own. A pid in use again keeps its folder, on the safe side.
void remove_stale_uploads(const fs::path& parent) {
    std::error_code ec;
    for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.compare(0, upload_prefix.size(), upload_prefix) != 0) continue;
        const std::size_t dash = name.find('-', upload_prefix.size());
        const std::string digits = name.substr(upload_prefix.size(), dash - upload_prefix.size());
        if (dash == std::string::npos || digits.empty() || digits.size() > 9 ||
            !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
            continue;
        const pid_t owner = pid_t(std::stol(digits));
        struct stat info {};
        if (::lstat(it->path().c_str(), &info) != 0 || !S_ISDIR(info.st_mode) || info.st_uid != ::getuid()) continue;
        if (owner == ::getpid() || ::kill(owner, 0) == 0 || errno != ESRCH) continue;
        std::error_code removed;
        fs::remove_all(it->path(), removed);
    }
}

}  // namespace

bool hsr::host::is_model_file_name(const std::string& name) {
    const std::string ext = lowercase(fs::path(name).extension().string());
    return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl" || ext == ".gltf" || ext == ".glb" ||
           ext == ".scene";
}

hsr::host::ModelCatalog::ModelCatalog(std::vector<fs::path> folders, const fs::path& upload_parent)
    : folders_(std::move(folders)) {
    for (fs::path& folder : folders_) {
        std::error_code ec;
        const fs::path absolute = fs::absolute(folder, ec);
        if (!ec) folder = absolute.lexically_normal();
    }
    remove_stale_uploads(upload_parent);
    std::string pattern = (upload_parent / fmt::format("{}{}-XXXXXX", upload_prefix, ::getpid())).string();
    if (::mkdtemp(pattern.data()) == nullptr)
        throw hsr::Error("cannot make a folder for uploads in {}", upload_parent.string());
    upload_dir_ = fs::canonical(pattern);
}

hsr::host::ModelCatalog::~ModelCatalog() {
    std::error_code ec;
    fs::remove_all(upload_dir_, ec);
}

std::vector<hsr::host::ModelEntry> hsr::host::ModelCatalog::list() const {
    std::vector<ModelEntry> out;
    for (std::size_t i = 0; i < folders_.size(); ++i) list_folder(i, folders_[i], out);
    {
        std::lock_guard lock(uploads_mutex_);
        for (const auto& [id, entry] : uploads_) out.push_back(entry);
    }
    std::sort(out.begin(), out.end(), [](const ModelEntry& a, const ModelEntry& b) { return a.id < b.id; });
    return out;
}

hsr::host::ModelEntry hsr::host::ModelCatalog::find(const std::string& id, hsr::Language language) const {
    {
        std::lock_guard lock(uploads_mutex_);
        const auto upload = uploads_.find(id);
        if (upload != uploads_.end()) return upload->second;
    }
    // Only the folder the id names is listed.
    const std::size_t slash = id.find('/');
    if (slash != std::string::npos && slash > 0 && slash <= 3 &&
        std::all_of(id.begin(), id.begin() + long(slash), [](char c) { return c >= '0' && c <= '9'; })) {
        const std::size_t index = std::stoul(id.substr(0, slash));
        if (index < folders_.size()) {
            std::vector<ModelEntry> models;
            list_folder(index, folders_[index], models);
            for (ModelEntry& model : models)
                if (model.id == id) return std::move(model);
        }
    }
    throw ViewError(404, "model", hsr::say(language, "no model '{}'", "модели «{}» нет", hsr::printable(id, hsr::kMaxQuotedPathChars)));
}

namespace {

// A scene's relative `mesh` paths made absolute against `folder`; every line keeps its number.
std::string with_mesh_folder(const std::string& text, const fs::path& folder) {
    constexpr auto npos = std::string::npos;
    std::string out;
    std::size_t begin = 0;
    while (begin <= text.size()) {
        std::size_t stop = text.find('\n', begin);
        if (stop == npos) stop = text.size();
        std::string line = text.substr(begin, stop - begin);
        const std::size_t start = line.find_first_not_of(" \t");
        if (start != npos && line.compare(start, 4, "mesh") == 0 && start + 4 < line.size() &&
            (line[start + 4] == ' ' || line[start + 4] == '\t')) {
            const std::size_t word = line.find_first_not_of(" \t", start + 4);
            std::size_t end = npos;
            std::string path;
            if (word != npos && line[word] == '"') {
                end = line.find('"', word + 1);
                if (end != npos) path = line.substr(word + 1, end - word - 1), ++end;
            } else if (word != npos) {
                end = std::min(line.find_first_of(" \t\r", word), line.size());
                path = line.substr(word, end - word);
            }
            if (!path.empty() && path[0] != '#' && fs::path(path).is_relative()) {
                const std::string full = (folder / path).lexically_normal().string();
                if (full.find('"') == npos) line = line.substr(0, word) + '"' + full + '"' + line.substr(end);
            }
        }
        out += line;
        if (stop == text.size()) break;
        out += '\n';
        begin = stop + 1;
    }
    return out;
}

}  // namespace

std::string hsr::host::ModelCatalog::scene_text(const std::string& id, uint64_t max_bytes, hsr::Language language) const {
    const ModelEntry entry = find(id, language);
    if (lowercase(entry.path.extension().string()) != ".scene")
        throw ViewError(400, "model", hsr::say(language, "model '{}' is not a .scene file", "модель «{}» — не файл .scene",
                                               hsr::printable(id, hsr::kMaxQuotedPathChars)));
    std::ifstream in(entry.path, std::ios::binary);
    std::string text;
    if (in) text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) throw ViewError(500, "", hsr::say(language, "cannot read the scene file", "не удалось прочитать файл сцены"));
    if (text.size() > max_bytes)
        throw ViewError(413, "model", hsr::say(language, "the scene file is over the upload-bytes limit",
                                               "файл сцены больше предела upload-bytes"));
    return text;
}

std::string hsr::host::ModelCatalog::add_upload(const std::string& file_name, const std::string& bytes_in,
                                                const std::string& replaces, const std::string& base_model,
                                                hsr::Language language) {
    // The name is kept for the id and the file's extension; the file itself is upload_dir/<n><ext>.
    const std::string& name = file_name;
    const bool plain = !name.empty() && name[0] != '.' && name.size() <= 100 &&
                       std::all_of(name.begin(), name.end(), [](unsigned char c) {
                           return std::isalnum(c) || c == '.' || c == '-' || c == '_' || c == ' ';
                       });
    if (!plain)
        throw ViewError(400, "X-File-Name",
                        hsr::say(language,
                                 "upload: file name '{}': expected a plain name such as bunny.obj "
                                 "(letters, digits, '.', '-', '_', spaces)",
                                 "загрузка: имя файла «{}»: ожидалось простое имя вроде bunny.obj "
                                 "(буквы, цифры, «.», «-», «_», пробелы)",
                                 hsr::printable(file_name)));
    const std::string ext = lowercase(fs::path(name).extension().string());
    // A .scene upload reads its meshes only inside the served folders and the uploads (read_policy).
    if (!is_model_file_name(name))
        throw ViewError(400, "X-File-Name",
                        hsr::say(language, "upload: '{}' is not a model file (.obj, .off, .ply, .stl, .gltf, .glb or .scene)",
                                 "загрузка: «{}» — не файл модели (.obj, .off, .ply, .stl, .gltf, .glb или .scene)", name));
    std::string based;
    if (ext == ".scene" && !base_model.empty() && base_model.rfind("upload/", 0) != 0) {
        const ModelEntry base = find(base_model, language);
        if (!base.scene)
            throw ViewError(400, "X-Base-Model", hsr::say(language, "upload: X-Base-Model must name a served .scene model",
                                                          "загрузка: X-Base-Model должен называть файл .scene, который показывает сервер"));
        based = with_mesh_folder(bytes_in, base.path.parent_path());
    }
    const std::string& bytes = based.empty() ? bytes_in : based;
    std::lock_guard lock(uploads_mutex_);
    if (const auto replaced = uploads_.find(replaces); !replaces.empty() && replaced != uploads_.end()) {
        std::error_code ec;
        fs::remove(replaced->second.path, ec);
        uploads_.erase(replaced);
    }
    const uint64_t n = next_upload_++;
    ModelEntry entry;
    entry.id = fmt::format("upload/{}/{}", n, name);
    entry.name = name;
    entry.path = upload_dir_ / fmt::format("{}{}", n, ext);
    entry.bytes = bytes.size();
    entry.scene = ext == ".scene";
    {
        std::ofstream out(entry.path, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        if (!out) throw ViewError(500, "", hsr::say(language, "upload: cannot store the file", "загрузка: не удалось сохранить файл"));
    }
    uploads_[entry.id] = entry;
    while (uploads_.size() > max_uploads) {
        auto oldest = std::min_element(uploads_.begin(), uploads_.end(), [](const auto& a, const auto& b) {
            return std::stoull(a.first.substr(7)) < std::stoull(b.first.substr(7));
        });
        std::error_code ec;
        fs::remove(oldest->second.path, ec);
        uploads_.erase(oldest);
    }
    return entry.id;
}

std::vector<fs::path> hsr::host::ModelCatalog::read_folders() const {
    std::vector<fs::path> folders = folders_;
    folders.push_back(upload_dir_);
    return folders;
}

hsr::ReadPolicy hsr::host::ModelCatalog::read_policy() const { return served_read_policy(read_folders()); }

hsr::ReadPolicy hsr::host::served_read_policy(std::vector<fs::path> folders) {
    return hsr::ReadPolicy(std::move(folders), "the folders hsr view serves");
}
