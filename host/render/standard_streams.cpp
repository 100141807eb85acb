// hsr render's standard input and output (standard_streams.hpp).
#include "render/standard_streams.hpp"

#include "hsr/error.hpp"
#include "hsr/limits.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>
#include <vector>

namespace fs = std::filesystem;

namespace hsr::host {
namespace {

int picture_descriptor = STDOUT_FILENO;

// Reads descriptor fd to its end, refusing more than `limit` bytes.
std::vector<char> read_all(int fd, uint64_t limit) {
    std::vector<char> bytes;
    std::vector<char> chunk(1 << 16);
    for (;;) {
        const ssize_t got = ::read(fd, chunk.data(), chunk.size());
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw hsr::Error("cannot read standard input: {}", std::strerror(errno));
        if (got == 0) return bytes;
        if (bytes.size() + uint64_t(got) > limit)
            throw hsr::LimitError("standard input: more than {} bytes, over the limit of {} (raise it with --limit "
                                  "model-bytes=N)", limit, limit);
        bytes.insert(bytes.end(), chunk.data(), chunk.data() + got);
    }
}

void write_all(int fd, const char* data, size_t size, const char* what) {
    while (size > 0) {
        const ssize_t put = ::write(fd, data, size);
        if (put < 0 && errno == EINTR) continue;
        if (put < 0) throw hsr::Error("cannot write {}: {}", what, std::strerror(errno));
        data += put;
        size -= size_t(put);
    }
}

}  // namespace

StdinModel::StdinModel(const std::string& format) {
    const std::vector<char> bytes = read_all(STDIN_FILENO, hsr::limits().model_bytes);
    std::error_code ec;
    std::string folder_template = (fs::temp_directory_path(ec) / "hsr-stdin-XXXXXX").string();
    if (ec || ::mkdtemp(folder_template.data()) == nullptr)
        throw hsr::Error("cannot make a temporary folder for standard input: {}",
                         ec ? ec.message() : std::strerror(errno));
    folder_ = folder_template;
    path_ = folder_ / ("stdin." + format);
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        const int error = errno;
        fs::remove_all(folder_, ec);
        throw hsr::Error("cannot keep standard input in a temporary file: {}", std::strerror(error));
    }
    try {
        write_all(fd, bytes.data(), bytes.size(), "standard input to a temporary file");
    } catch (...) {
        ::close(fd);
        fs::remove_all(folder_, ec);
        throw;
    }
    ::close(fd);
}

StdinModel::~StdinModel() {
    std::error_code ec;
    fs::remove_all(folder_, ec);
}

void reserve_standard_output() {
    std::fflush(stdout);
    const int kept = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    if (kept < 0) throw hsr::Error("cannot keep standard output for the picture: {}", std::strerror(errno));
    if (::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
        ::close(kept);
        throw hsr::Error("cannot keep standard output for the picture: {}", std::strerror(errno));
    }
    picture_descriptor = kept;
    std::signal(SIGPIPE, SIG_IGN);
}

void write_standard_output(std::span<const uint8_t> bytes) {
    write_all(picture_descriptor, reinterpret_cast<const char*>(bytes.data()), bytes.size(),
              "the picture to standard output");
}

}  // namespace hsr::host
