// A command of hsr run as a child process, for work that must not take its caller down when a
// plugin crashes, aborts, exits or hangs in it: hsr view's workers, hsr bench's cells. The two talk
// over a socket (the child's fd 3) in messages, each its length as 8 little-endian bytes and then its
// bytes; what the child writes to stdout and stderr is read by the parent as it comes and the end of
// it kept, so that a child that dies can be asked what killed it (hsr/plugin_faults.hpp writes the
// line that names the plugin).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace hsr::host {

// The child's end of the socket.
inline constexpr int kChildSocketFd = 3;

// The running executable (/proc/self/exe): the program a command starts its children from.
std::filesystem::path running_executable();

class ChildProcess {
public:
    // Starts `executable args...` with stdin from /dev/null, stdout and stderr into the parent, the
    // socket on fd 3, no other file of the parent open, and no signal blocked. Throws hsr::Error.
    ChildProcess(const std::filesystem::path& executable, const std::vector<std::string>& args);
    // Kills the child (SIGKILL) if it still runs, and reaps it.
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    // Sends one message; false when the child is gone.
    bool send(std::string_view message);

    enum class Received {
        kMessage,    // `message` holds the next message
        kTimedOut,   // the deadline passed first
        kCancelled,  // *cancel became true first (looked at every 50 ms)
        kGone,       // the child closed its socket, or sent a message over max_bytes (it is killed)
    };
    Received receive(std::string& message, std::chrono::steady_clock::time_point deadline,
                     const std::atomic<bool>* cancel = nullptr, uint64_t max_bytes = uint64_t(1) << 34);

    // Kills the child (SIGKILL) if it runs; then waits for it and says how it ended: "exited with
    // status 3", "was killed by SIGSEGV". Waits for the child's end if it was not killed.
    std::string kill_and_reap();
    // The same without killing it: for a child that is known to be gone (receive() said kGone).
    std::string reap();

    // The last 8 KiB the child wrote to stdout and stderr.
    const std::string& output_tail() const { return output_tail_; }
    int pid() const { return pid_; }
    bool running() const { return pid_ > 0 && !reaped_; }

private:
    void read_output();  // what the output pipe holds now, without blocking

    int pid_ = -1;
    int socket_ = -1;
    int output_ = -1;
    bool reaped_ = false;
    int status_ = 0;
    std::string pending_;  // bytes of the next message received so far
    std::string output_tail_;
};

// The child's side: reads the next message from fd (false at the end of input, on an error, or for
// a message over max_bytes), and writes one (false when the parent is gone).
bool read_message(int fd, std::string& message, uint64_t max_bytes = uint64_t(1) << 34);
bool write_message(int fd, std::string_view message);
// One message made of these parts one after the other, without joining them first.
bool write_message(int fd, std::initializer_list<std::string_view> parts);

}  // namespace hsr::host
