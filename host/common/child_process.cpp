// Child processes of hsr (child_process.hpp): posix_spawn, a socket pair for messages and one pipe
// for the child's output, both read by poll() so that a child writing much to stderr never blocks.
#include "common/child_process.hpp"

#include "hsr/error.hpp"
#include "hsr/plugin_faults.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

extern char** environ;

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kOutputTailBytes = 8192;
constexpr int kPollSliceMs = 50;

std::string status_text(int status) {
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return std::string("was killed by ") + hsr::signal_name(WTERMSIG(status));
    return "ended with status " + std::to_string(status);
}

void close_fd(int& fd) {
    if (fd >= 0) ::close(fd);
    fd = -1;
}

bool write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

bool read_all(int fd, char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::read(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

std::array<char, 8> length_prefix(uint64_t length) {
    std::array<char, 8> bytes{};
    for (int i = 0; i < 8; ++i) bytes[i] = static_cast<char>((length >> (8 * i)) & 0xff);
    return bytes;
}

uint64_t length_of(const char* bytes) {
    uint64_t length = 0;
    for (int i = 0; i < 8; ++i) length |= uint64_t(static_cast<unsigned char>(bytes[i])) << (8 * i);
    return length;
}

}  // namespace

fs::path hsr::host::running_executable() {
    std::error_code ec;
    fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw hsr::Error("cannot find the running executable (/proc/self/exe: {})", ec.message());
    return self;
}

hsr::host::ChildProcess::ChildProcess(const fs::path& executable, const std::vector<std::string>& args) {
    int sockets[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0)
        throw hsr::Error("cannot start a child process (socketpair: {})", std::strerror(errno));
    int output[2];
    if (::pipe2(output, O_CLOEXEC) != 0) {
        const int error = errno;
        ::close(sockets[0]);
        ::close(sockets[1]);
        throw hsr::Error("cannot start a child process (pipe: {})", std::strerror(error));
    }
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&files, output[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&files, output[1], STDERR_FILENO);
    posix_spawn_file_actions_adddup2(&files, sockets[1], kChildSocketFd);
    // The listening socket and the clients' connections of hsr view must not live on in a child.
    posix_spawn_file_actions_addclosefrom_np(&files, kChildSocketFd + 1);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (int sig : {SIGINT, SIGTERM, SIGPIPE, SIGCHLD}) sigaddset(&defaults, sig);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);

    std::vector<std::string> words{executable.string()};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    const int failed = ::posix_spawn(&pid, executable.c_str(), &files, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    posix_spawnattr_destroy(&attributes);
    ::close(sockets[1]);
    ::close(output[1]);
    if (failed != 0) {
        ::close(sockets[0]);
        ::close(output[0]);
        throw hsr::Error("cannot start {} ({})", executable.string(), std::strerror(failed));
    }
    pid_ = pid;
    socket_ = sockets[0];
    output_ = output[0];
    ::fcntl(output_, F_SETFL, ::fcntl(output_, F_GETFL) | O_NONBLOCK);
}

hsr::host::ChildProcess::~ChildProcess() {
    if (running()) kill_and_reap();
    close_fd(socket_);
    close_fd(output_);
}

bool hsr::host::ChildProcess::send(std::string_view message) {
    if (socket_ < 0) return false;
    const std::array<char, 8> prefix = length_prefix(message.size());
    return write_all(socket_, prefix.data(), prefix.size()) && write_all(socket_, message.data(), message.size());
}

void hsr::host::ChildProcess::read_output() {
    char buffer[4096];
    while (output_ >= 0) {
        const ssize_t n = ::read(output_, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
        if (n <= 0) {
            close_fd(output_);
            return;
        }
        output_tail_.append(buffer, static_cast<std::size_t>(n));
        if (output_tail_.size() > 2 * kOutputTailBytes) output_tail_.erase(0, output_tail_.size() - kOutputTailBytes);
    }
}

hsr::host::ChildProcess::Received hsr::host::ChildProcess::receive(std::string& message,
                                                                   std::chrono::steady_clock::time_point deadline,
                                                                   const std::atomic<bool>* cancel, uint64_t max_bytes) {
    using std::chrono::steady_clock;
    for (;;) {
        if (pending_.size() >= 8) {
            const uint64_t length = length_of(pending_.data());
            if (length > max_bytes) {
                kill_and_reap();
                close_fd(socket_);
                return Received::kGone;
            }
            if (pending_.size() - 8 >= length) {
                if (pending_.size() - 8 == length) {  // the usual case: no byte of the next one yet
                    pending_.erase(0, 8);
                    message = std::move(pending_);
                    pending_.clear();
                } else {
                    message.assign(pending_, 8, length);
                    pending_.erase(0, 8 + length);
                }
                return Received::kMessage;
            }
        }
        if (socket_ < 0) return Received::kGone;
        if (cancel != nullptr && cancel->load()) return Received::kCancelled;
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - steady_clock::now()).count();
        if (left <= 0) return Received::kTimedOut;
        pollfd fds[2] = {{socket_, POLLIN, 0}, {output_, POLLIN, 0}};
        const int ready = ::poll(fds, output_ >= 0 ? 2 : 1, static_cast<int>(std::min<long long>(left, kPollSliceMs)));
        if (ready < 0 && errno != EINTR) return Received::kGone;
        if (ready <= 0) continue;
        if (output_ >= 0 && fds[1].revents != 0) read_output();
        if (fds[0].revents == 0) continue;
        // Large messages come in large reads: grow the buffer to what the length prefix announces.
        std::size_t want = 1 << 16;
        if (pending_.size() >= 8) {
            const uint64_t length = length_of(pending_.data());
            if (length <= max_bytes) {
                pending_.reserve(8 + length);  // once, rather than doubling as it comes
                want = std::max<std::size_t>(want, std::min<uint64_t>(8 + length - pending_.size(), 1 << 24));
            }
        }
        const std::size_t old_size = pending_.size();
        pending_.resize(old_size + want);
        const ssize_t n = ::read(socket_, pending_.data() + old_size, want);
        pending_.resize(old_size + std::max<ssize_t>(n, 0));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            close_fd(socket_);
            read_output();
            return Received::kGone;
        }
    }
}

std::string hsr::host::ChildProcess::kill_and_reap() {
    if (running()) ::kill(pid_, SIGKILL);
    return reap();
}

std::string hsr::host::ChildProcess::reap() {
    if (pid_ <= 0) return "was never started";
    if (!reaped_) {
        while (::waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
        }
        reaped_ = true;
        // What it wrote last, until the pipe's end (its other holders, if any, are its own children).
        if (output_ >= 0) {
            pollfd fd{output_, POLLIN, 0};
            while (output_ >= 0 && ::poll(&fd, 1, 100) > 0) {
                const std::size_t before = output_tail_.size();
                read_output();
                if (output_tail_.size() == before) break;
            }
        }
    }
    return status_text(status_);
}

bool hsr::host::read_message(int fd, std::string& message, uint64_t max_bytes) {
    char prefix[8];
    if (!read_all(fd, prefix, sizeof prefix)) return false;
    const uint64_t length = length_of(prefix);
    if (length > max_bytes) return false;
    message.resize(length);
    return read_all(fd, message.data(), length);
}

bool hsr::host::write_message(int fd, std::string_view message) { return write_message(fd, {message}); }

bool hsr::host::write_message(int fd, std::initializer_list<std::string_view> parts) {
    uint64_t length = 0;
    for (std::string_view part : parts) length += part.size();
    const std::array<char, 8> prefix = length_prefix(length);
    if (!write_all(fd, prefix.data(), prefix.size())) return false;
    for (std::string_view part : parts)
        if (!write_all(fd, part.data(), part.size())) return false;
    return true;
}
