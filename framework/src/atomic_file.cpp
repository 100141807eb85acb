// AtomicFile and AtomicFileSet (hsr/atomic_file.hpp): a temporary beside the target, synced and
// renamed over it when complete; removed on failure, and on SIGINT, SIGTERM and SIGHUP.
#include "hsr/atomic_file.hpp"

#include "hsr/error.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <mutex>
#include <random>
#include <string>

namespace hsr {
namespace {

namespace fs = std::filesystem;

// The temporaries that exist, where the signal handler can find them. The handler may only call
// async-signal-safe functions (unlink, signal, raise) and read memory nobody frees or locks: fixed
// slots, each filled in before it is armed (std::atomic<int> is lock-free).
constexpr int slot_free = 0, slot_filling = 1, slot_armed = 2;
struct TemporarySlot {
    std::atomic<int> state{slot_free};
    char path[PATH_MAX];
};
TemporarySlot temporary_slots[32];

// The handler runs on any thread while the others go on, so a temporary created on another thread
// between the handler's look at the slots and the end of the process would be left behind. Creating
// a temporary and arming its slot is therefore one step the handler waits for (`creating`), and once
// the handler has begun (`terminating`) no thread creates another.
std::atomic<bool> terminating{false};
std::atomic<int> creating{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

void remove_temporaries_and_reraise(int signal_number) {
    terminating.store(true);
    while (creating.load() != 0) {
    }
    for (TemporarySlot& slot : temporary_slots)
        if (slot.state.load() == slot_armed) ::unlink(slot.path);
    ::signal(signal_number, SIG_DFL);
    ::raise(signal_number);  // delivered on return: the process ends as the signal asked
}

// Blocks the handled signals on this thread (so the handler, which waits for `creating`, never runs
// on it) and counts it in `creating` for the lifetime of the guard. When the process is already
// ending by a signal, it waits for that end instead.
class CreatingTemporary {
public:
    CreatingTemporary() {
        sigset_t handled;
        sigemptyset(&handled);
        for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&handled, signal_number);
        ::pthread_sigmask(SIG_BLOCK, &handled, &previous_);
        creating.fetch_add(1);
        if (terminating.load()) {
            creating.fetch_sub(1);
            for (;;) ::pause();  // another thread's handler is ending the process
        }
    }
    ~CreatingTemporary() {
        creating.fetch_sub(1);
        ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
    }
    CreatingTemporary(const CreatingTemporary&) = delete;
    CreatingTemporary& operator=(const CreatingTemporary&) = delete;

private:
    sigset_t previous_;
};

void install_signal_handlers() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction current {};
            if (::sigaction(signal_number, nullptr, &current) != 0) continue;
            if ((current.sa_flags & SA_SIGINFO) != 0 || current.sa_handler != SIG_DFL) continue;  // not ours to change
            struct sigaction handler {};
            handler.sa_handler = &remove_temporaries_and_reraise;
            sigemptyset(&handler.sa_mask);
            ::sigaction(signal_number, &handler, nullptr);
        }
    });
}

// The slot now holding path, or -1 when none is free (the temporary then outlives a signal).
int arm_slot(const std::string& path) {
    if (path.size() >= PATH_MAX) return -1;
    for (int i = 0; i < int(std::size(temporary_slots)); ++i) {
        int expected = slot_free;
        if (!temporary_slots[i].state.compare_exchange_strong(expected, slot_filling)) continue;
        std::memcpy(temporary_slots[i].path, path.c_str(), path.size() + 1);
        temporary_slots[i].state.store(slot_armed);
        return i;
    }
    return -1;
}

void free_slot(int slot) {
    if (slot >= 0) temporary_slots[slot].state.store(slot_free);
}

// ".<name>.tmp-<pid>-<random>" in destination's folder; the name is shortened so that the whole
// stays within the 255 bytes a file name may have.
fs::path temporary_name(const fs::path& destination) {
    static std::random_device random;
    const std::string name = destination.filename().string().substr(0, 200);
    const uint64_t bits = (uint64_t(random()) << 32) ^ random();
    return destination.parent_path() / fmt::format(".{}.tmp-{}-{:016x}", name, ::getpid(), bits);
}

std::string last_error() { return errno != 0 ? std::strerror(errno) : "write error"; }

// Unbuffered: each write goes straight to the stdio stream, which buffers, so that the C++ stream
// and stdio() can be mixed.
class StdioBuffer : public std::streambuf {
public:
    explicit StdioBuffer(std::FILE* file) : file_(file) {}

protected:
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        return std::fputc(c, file_) == EOF ? traits_type::eof() : c;
    }
    std::streamsize xsputn(const char* text, std::streamsize count) override {
        return std::streamsize(std::fwrite(text, 1, size_t(count), file_));
    }

private:
    std::FILE* file_;
};

}  // namespace

fs::path AtomicFile::destination(const fs::path& target) {
    fs::path path = target;
    for (int hop = 0; hop < 40; ++hop) {  // Linux's own limit on links in a path
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(path, ec))) return path;
        const fs::path link = fs::read_symlink(path, ec);
        if (ec) return path;
        path = link.is_absolute() ? link : path.parent_path() / link;
    }
    throw Error("cannot write {}: too many levels of symbolic links", printable(target.string(), kMaxQuotedPathChars));
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)), destination_(destination(target_)) {
    install_signal_handlers();
    struct stat existing {};
    const bool exists = ::stat(destination_.c_str(), &existing) == 0;
    int fd = -1;
    if (exists && !S_ISREG(existing.st_mode)) {
        fd = ::open(destination_.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd < 0) {
            const std::string why = last_error();
            throw Error("cannot write {}: {}", printable(target_.string(), kMaxQuotedPathChars), why);
        }
    } else {
        const CreatingTemporary creating_temporary;
        for (int attempt = 0; fd < 0 && attempt < 16; ++attempt) {
            temporary_ = temporary_name(destination_);
            fd = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            if (fd < 0 && errno != EEXIST) break;
        }
        if (fd < 0) {
            const std::string why = last_error();
            temporary_.clear();
            throw Error("cannot write {}: {}", printable(target_.string(), kMaxQuotedPathChars), why);
        }
        signal_slot_ = arm_slot(temporary_.string());
        if (exists) ::fchmod(fd, existing.st_mode & 07777);  // the replacement keeps the file's permissions
    }
    file_ = ::fdopen(fd, "wb");
    if (file_ == nullptr) {
        const std::string why = last_error();
        ::close(fd);
        if (!temporary_.empty()) ::unlink(temporary_.c_str());
        free_slot(signal_slot_);
        throw Error("cannot write {}: {}", printable(target_.string(), kMaxQuotedPathChars), why);
    }
}

AtomicFile::~AtomicFile() {
    if (file_ != nullptr) std::fclose(file_);
    if (!temporary_.empty()) ::unlink(temporary_.c_str());
    free_slot(signal_slot_);
}

std::ostream& AtomicFile::stream() {
    if (file_ == nullptr) throw Error("{}: written after it was finished", printable(target_.string(), kMaxQuotedPathChars));
    if (!stream_) {
        buffer_ = std::make_unique<StdioBuffer>(file_);
        stream_ = std::make_unique<std::ostream>(buffer_.get());
    }
    return *stream_;
}

void AtomicFile::finish() {
    if (file_ == nullptr) return;
    errno = 0;
    bool ok = !(stream_ && stream_->fail()) && std::fflush(file_) == 0 && std::ferror(file_) == 0;
    if (ok && !temporary_.empty()) ok = ::fsync(::fileno(file_)) == 0;  // on disk before the rename
    std::string why = ok ? "" : last_error();
    if (std::fclose(file_) != 0 && ok) {
        ok = false;
        why = last_error();
    }
    file_ = nullptr;
    stream_.reset();
    buffer_.reset();
    if (!ok) throw Error("cannot write {}: {}", printable(target_.string(), kMaxQuotedPathChars), why);
}

void AtomicFile::commit() {
    finish();
    if (temporary_.empty()) return;
    if (::rename(temporary_.c_str(), destination_.c_str()) != 0) {
        const std::string why = last_error();
        throw Error("cannot write {}: {}", printable(target_.string(), kMaxQuotedPathChars), why);
    }
    temporary_.clear();
    free_slot(signal_slot_);
    signal_slot_ = -1;
}

AtomicFile& AtomicFileSet::add(fs::path target) {
    files_.push_back(std::make_unique<AtomicFile>(std::move(target)));
    return *files_.back();
}

void AtomicFileSet::commit() {
    for (const auto& file : files_) file->finish();
    for (const auto& file : files_) file->commit();
    files_.clear();
}

void remove_temporaries_now() noexcept {
    terminating.store(true);
    for (TemporarySlot& slot : temporary_slots)
        if (slot.state.load() == slot_armed) ::unlink(slot.path);
}

}  // namespace hsr
