// ChildProcess (host/common/child_process.hpp) against /bin/sh children whose behaviour is known:
// messages both ways, the output captured, and each way a child can end told apart.
#include "common/child_process.hpp"

#include <catch2/catch.hpp>

#include <chrono>

using hsr::host::ChildProcess;
using namespace std::chrono_literals;

namespace {

ChildProcess shell(const std::string& script) { return ChildProcess("/bin/sh", {"-c", script}); }

auto in(std::chrono::milliseconds ms) { return std::chrono::steady_clock::now() + ms; }

}  // namespace

TEST_CASE("child process: a message each way, and the output kept", "[child-process]") {
    // Echoes the 8-byte length and the 5 bytes it is sent back, then ends.
    ChildProcess child = shell("echo starting >&2; head -c 13 <&3 >&3; echo done");
    REQUIRE(child.send("hello"));
    std::string message;
    REQUIRE(child.receive(message, in(10s)) == ChildProcess::Received::kMessage);
    CHECK(message == "hello");
    CHECK(child.receive(message, in(10s)) == ChildProcess::Received::kGone);
    CHECK(child.reap() == "exited with status 0");
    CHECK(child.output_tail() == "starting\ndone\n");
}

TEST_CASE("child process: how a child ended", "[child-process]") {
    std::string message;
    SECTION("a signal") {
        ChildProcess child = shell("echo 'hsr: error: plugin crashed' >&2; kill -SEGV $$");
        CHECK(child.receive(message, in(10s)) == ChildProcess::Received::kGone);
        CHECK(child.reap() == "was killed by SIGSEGV");
        CHECK(child.output_tail() == "hsr: error: plugin crashed\n");
    }
    SECTION("exit") {
        ChildProcess child = shell("exit 3");
        CHECK(child.receive(message, in(10s)) == ChildProcess::Received::kGone);
        CHECK(child.reap() == "exited with status 3");
    }
    SECTION("a time limit, then killed") {
        ChildProcess child = shell("sleep 30");
        CHECK(child.receive(message, in(200ms)) == ChildProcess::Received::kTimedOut);
        CHECK(child.running());
        CHECK(child.kill_and_reap() == "was killed by SIGKILL");
        CHECK_FALSE(child.running());
    }
    SECTION("cancelled") {
        ChildProcess child = shell("sleep 30");
        std::atomic<bool> cancel{true};
        CHECK(child.receive(message, in(10s), &cancel) == ChildProcess::Received::kCancelled);
    }
    SECTION("a message over the size allowed") {
        ChildProcess child = shell("printf '\\377\\377\\377\\377\\0\\0\\0\\0' >&3; sleep 30");
        CHECK(child.receive(message, in(10s), nullptr, 1000) == ChildProcess::Received::kGone);
        CHECK_FALSE(child.running());
    }
    SECTION("a program that does not exist") {
        CHECK_THROWS(ChildProcess("/nonexistent/program", {}));
    }
}

TEST_CASE("child process: the child holds none of the parent's files", "[child-process]") {
    ChildProcess child = shell("ls /proc/self/fd >&2");
    std::string message;
    CHECK(child.receive(message, in(10s)) == ChildProcess::Received::kGone);
    child.reap();
    // stdin, stdout, stderr, the socket, and ls's own directory handle.
    CHECK(child.output_tail() == "0\n1\n2\n3\n4\n");
}
