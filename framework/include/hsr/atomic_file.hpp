// Output files written whole or not at all. An AtomicFile writes into a temporary file beside its
// target (".<name>.tmp-<pid>-<random>", created with O_EXCL, so that two writers never share one),
// and commit() flushes it to disk and renames it over the target: whoever reads the target, and
// whenever the writer dies, finds the old file or the complete new one, never a mix. An
// AtomicFileSet holds the outputs of one command and renames them only once every one of them is
// complete, so a command that fails part-way leaves all its targets as they were.
//
// A temporary that is not committed is removed when its AtomicFile is destroyed (an error or an
// exception on the way) and, by a handler installed with the first AtomicFile, on SIGINT, SIGTERM
// and SIGHUP (unless the program has its own handler for them or ignores them), and when a plugin
// crashes or calls exit() during a call (plugin_faults.hpp). SIGKILL, or a power cut, can leave a
// ".<name>.tmp-..." file behind, never a truncated target.
//
// A symbolic link is followed: the file it names is replaced and the link kept. A target that exists
// and is not a regular file (a device such as /dev/null, a pipe) is written in place: there is no
// file to keep, and renaming over it would replace the device.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <ostream>
#include <streambuf>
#include <vector>

namespace hsr {

class AtomicFile {
public:
    // Creates the temporary; throws hsr::Error naming target when it cannot.
    explicit AtomicFile(std::filesystem::path target);
    ~AtomicFile();  // closes and removes the temporary unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // The name given, for messages.
    const std::filesystem::path& target() const { return target_; }

    // Where the contents go until commit(), as a stdio stream (for libpng and Cairo's write
    // callbacks) or a C++ stream; both write to the same place. Write errors are reported by
    // finish() and commit().
    std::FILE* stdio() const { return file_; }
    std::ostream& stream();

    // Flushes the contents to disk and closes the temporary; throws hsr::Error when a write failed.
    // Called again, does nothing.
    void finish();
    // finish(), then renames the temporary over the target.
    void commit();

    // The file that writing to target replaces: target with its symbolic links followed. Throws
    // hsr::Error for a loop of links.
    static std::filesystem::path destination(const std::filesystem::path& target);

private:
    std::filesystem::path target_, destination_;
    std::filesystem::path temporary_;  // empty when written in place, or once renamed or removed
    std::FILE* file_ = nullptr;        // null once finished
    int signal_slot_ = -1;             // where the signal handler finds temporary_, or -1
    std::unique_ptr<std::streambuf> buffer_;
    std::unique_ptr<std::ostream> stream_;
};

// The files of one command: each add() starts one; commit() finishes all of them and only then
// renames each over its target. Destroyed without commit() (an error, an exception), it removes
// every temporary. The renames come last and in a row; one of them fails only if the folder changes
// under the command, and then the files renamed before it stay replaced.
class AtomicFileSet {
public:
    AtomicFile& add(std::filesystem::path target);
    void commit();

private:
    std::vector<std::unique_ptr<AtomicFile>> files_;
};

// Removes every temporary not yet committed, for a handler about to end the process: async-signal-
// safe. It does not wait for a temporary another thread is creating at that moment, which may stay.
// Afterwards no thread creates another.
void remove_temporaries_now() noexcept;

}  // namespace hsr
