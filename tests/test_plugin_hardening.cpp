// A broken library on the plugin path (tests/plugins/bad_library.c, one per folder) must not take
// the hsr executable down: `hsr plugins` lists it as refused with the reason, a command that does not
// use it works as if it were absent, and asking for it is a one-line error. Also the descriptor
// check's bounds, in-process, against strings and tables that end at an unmapped page.
#include "cli_support.hpp"
#include "hsr/abi.h"
#include "hsr/plugin_registry.hpp"

#include <catch2/catch.hpp>

#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using cli::Run;
using cli::scratch_dir;
using cli::slurp;

// The folder that holds the one broken library of that case.
std::string bad_folder(const std::string& name) { return std::string(HSR_TEST_PLUGIN_DIR) + "/" + name; }

// Runs `hsr <args> --plugin-path <the case's folder>` with a time limit.
Run run_hsr_beside(const std::string& name, const std::string& args, const std::string& tag) {
    return cli::run_hsr(args + " --plugin-path " + bad_folder(name), name + "-" + tag);
}

std::string cube() { return std::string(HSR_MODELS_DIR) + "/cube.obj"; }

// One line naming the problem, exit status 1.
void require_plugin_error(const Run& r, const std::string& expected) {
    cli::require_one_line_error(r, expected);
    CHECK(r.status == 1);
}

// A render with the default plugins succeeds beside the broken library.
void require_default_render_works(const std::string& name) {
    const fs::path png = scratch_dir() / (name + ".png");
    fs::remove(png);
    const Run r = run_hsr_beside(name, "render " + cube() + " --width 64 --height 64 -o " + png.string(), "render");
    INFO("stderr: " << r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Catch::StartsWith("wrote ") && !Catch::Contains("hsr: error") && !Catch::Contains("hsr: warning"));
    CHECK(fs::exists(png));
}

// The whole contract for a library that must be refused.
void require_refused(const std::string& name, const std::string& reason) {
    const Run listing = run_hsr_beside(name, "plugins", "plugins");
    INFO("stdout: " << listing.out << "\nstderr: " << listing.err);
    CHECK(listing.status == 0);
    CHECK_THAT(listing.out, Catch::Contains("refused: " + bad_folder(name) + "/" + name + ".so"));
    CHECK_THAT(listing.out, Catch::Contains(reason));
    CHECK_THAT(listing.out, Catch::Contains("hidden-surface  zbuffer"));  // the good plugins are still listed
    CHECK(std::count(listing.out.begin(), listing.out.end(), '\n') < 200);

    require_default_render_works(name);

    const Run asked = run_hsr_beside(name, "render " + cube() + " --width 64 --height 64 -o x.png -a " + name, "asked");
    require_plugin_error(asked, "no hidden-surface or hidden-line plugin named '" + name + "'");
    CHECK_THAT(asked.err, Catch::Contains("refused: ") && Catch::Contains(reason));
}

}  // namespace

TEST_CASE("plugin hardening: an entry symbol that is data, not a function", "[plugin-hardening]") {
    require_refused("entry-is-data", "'hsr_plugin_entry' is not a function");
}

TEST_CASE("plugin hardening: a NULL api name", "[plugin-hardening]") {
    require_refused("null-api", "it is not an hsr plugin (api name differs)");
}

TEST_CASE("plugin hardening: a NULL plugin name", "[plugin-hardening]") {
    // Refused before it has a name, so it is found by its file name when asked for.
    require_refused("null-name", "it has no name");
}

TEST_CASE("plugin hardening: a NULL parameter table with a parameter count", "[plugin-hardening]") {
    require_refused("null-params", "its parameter table is missing");
}

TEST_CASE("plugin hardening: a NULL interface table", "[plugin-hardening]") {
    require_refused("null-interface-table", "it has no interface table");
}

TEST_CASE("plugin hardening: a version string pointing into unmapped memory", "[plugin-hardening]") {
    require_refused("wild-version", "crashed while loading (signal 11");
}

TEST_CASE("plugin hardening: an interface table pointing into unmapped memory", "[plugin-hardening]") {
    require_refused("wild-interface-table", "crashed while loading (signal 11");
}

TEST_CASE("plugin hardening: a name without a NUL within 256 bytes", "[plugin-hardening]") {
    require_refused("unterminated-name", "its name does not end within 256 bytes");
}

TEST_CASE("plugin hardening: a parameter count past the parameter array", "[plugin-hardening]") {
    require_refused("huge-param-count", "it declares 2147483648 parameters, more than the 256 allowed");
    require_refused("huge-phase-count", "it declares 2147483648 phases, more than the 256 allowed");
    require_refused("huge-translation-count", "it declares 2147483648 translations, more than the 8192 allowed");
}

TEST_CASE("plugin hardening: a kind outside hsr_plugin_kind", "[plugin-hardening]") {
    require_refused("kind-99", "unknown plugin kind 99");
}

TEST_CASE("plugin hardening: a constructor that segfaults", "[plugin-hardening]") {
    require_refused("constructor-segfault", "crashed while loading (signal 11");
}

TEST_CASE("plugin hardening: a constructor that calls exit", "[plugin-hardening]") {
    require_refused("constructor-exit", "exited while loading (status 3)");
}

TEST_CASE("plugin hardening: a constructor that never returns", "[plugin-hardening][slow]") {
    require_refused("constructor-hang", "timed out while loading");
}

TEST_CASE("plugin hardening: an error message without a terminating NUL", "[plugin-hardening]") {
    const Run listing = run_hsr_beside("unterminated-error", "plugins", "plugins");
    CHECK(listing.status == 0);
    CHECK_THAT(listing.out, Catch::Contains("hidden-surface  unterminated-error"));
    require_default_render_works("unterminated-error");

    const Run asked = run_hsr_beside("unterminated-error", "render " + cube() + " --width 64 --height 64 -o x.png -a unterminated-error", "asked");
    require_plugin_error(asked, "failed in render (status 4): ");
    // The plugin filled all HSR_ERROR_MESSAGE_SIZE bytes with 'x'; the last one counts as the
    // terminator, and nothing after the buffer is printed.
    const std::string expected_tail = ": " + std::string(HSR_ERROR_MESSAGE_SIZE - 1, 'x') + "\n";
    CHECK(asked.err.size() >= expected_tail.size());
    CHECK(asked.err.substr(asked.err.size() - std::min(asked.err.size(), expected_tail.size())) == expected_tail);
}

TEST_CASE("plugin hardening: an exception thrown across the C ABI", "[plugin-hardening]") {
    const Run listing = run_hsr_beside("throws-across-abi", "plugins", "plugins");
    CHECK(listing.status == 0);
    CHECK_THAT(listing.out, Catch::Contains("hidden-surface  throws-across-abi"));
    require_default_render_works("throws-across-abi");

    const Run asked = run_hsr_beside("throws-across-abi", "render " + cube() + " --width 64 --height 64 -o x.png -a throws-across-abi", "asked");
    require_plugin_error(asked, "hidden-surface plugin 'throws-across-abi' let an exception escape from render");
}

TEST_CASE("plugin hardening: several broken libraries in one folder, good ones after them", "[plugin-hardening]") {
    // The libraries are checked one after the other in one child; each that kills it must be blamed
    // alone, and the checking go on with the next.
    const fs::path folder = scratch_dir() / "mixed";
    fs::remove_all(folder);
    fs::create_directories(folder);
    const std::vector<std::string> broken = {"constructor-exit", "constructor-segfault", "entry-is-data", "kind-99",
                                             "wild-version"};
    for (const std::string& name : broken)
        fs::copy_file(bad_folder(name) + "/" + name + ".so", folder / (name + ".so"));
    fs::copy_file(bad_folder("unterminated-error") + "/unterminated-error.so", folder / "unterminated-error.so");
    fs::copy_file(std::string(HSR_TEST_PLUGIN_DIR) + "/handmade-lines.so", folder / "zz-handmade-lines.so");

    const fs::path out = scratch_dir() / "mixed.out";
    const std::string command = "timeout 60 " + std::string(HSR_BINARY_DIR) + "/hsr plugins --plugin-path " +
                                folder.string() + " > " + out.string() + " 2>&1 < /dev/null";
    const int raw = std::system(command.c_str());
    const std::string listing = slurp(out);
    INFO(listing);
    CHECK((WIFEXITED(raw) && WEXITSTATUS(raw) == 0));
    CHECK_THAT(listing, Catch::Contains("constructor-exit.so: refused: exited while loading (status 3)"));
    CHECK_THAT(listing, Catch::Contains("constructor-segfault.so: refused: crashed while loading (signal 11"));
    CHECK_THAT(listing, Catch::Contains("entry-is-data.so: not an hsr plugin"));
    CHECK_THAT(listing, Catch::Contains("kind-99.so: plugin 'kind-99' refused: unknown plugin kind 99"));
    CHECK_THAT(listing, Catch::Contains("wild-version.so: refused: crashed while loading (signal 11"));
    size_t refused_lines = 0;
    for (size_t at = listing.find("\nrefused: "); at != std::string::npos; at = listing.find("\nrefused: ", at + 1))
        ++refused_lines;
    CHECK(refused_lines == broken.size());
    CHECK_THAT(listing, Catch::Contains("hidden-surface  unterminated-error"));
    CHECK_THAT(listing, Catch::Contains("hidden-line     handmade-lines"));
    CHECK_THAT(listing, Catch::Contains("hidden-surface  zbuffer"));
}

namespace {

// 64 KiB of readable memory followed by an unreadable page: whatever is placed at the end of the
// readable part cannot be read past without a SIGSEGV.
struct GuardedPage {
    static constexpr size_t readable = 64 * 1024;
    size_t page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
    char* base = nullptr;
    GuardedPage() {
        void* p = ::mmap(nullptr, readable + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        REQUIRE(p != MAP_FAILED);
        base = static_cast<char*>(p);
        REQUIRE(::mprotect(base + readable, page, PROT_NONE) == 0);
    }
    ~GuardedPage() { ::munmap(base, readable + page); }
    char* end() const { return base + readable; }
};

// A descriptor check_descriptor accepts, to break one field at a time.
struct GoodDescriptor {
    IHiddenSurfaceRemover table{};
    hsr_param_desc param{sizeof(hsr_param_desc), "level", HSR_PARAM_INT, "3", 0, 10, nullptr, "a level"};
    hsr_plugin_descriptor d{};
    GoodDescriptor() {
        table.struct_size = sizeof table;
        d = {sizeof d, HSR_API_NAME, HSR_ABI_MAJOR, HSR_ABI_MINOR, HSR_KIND_HIDDEN_SURFACE_REMOVER, "good",
             "1.0", "fine", &param, 1, &table};
    }
};

}  // namespace

TEST_CASE("plugin hardening: descriptor strings are read only within their bound", "[plugin-hardening]") {
    GoodDescriptor g;
    REQUIRE(hsr::check_descriptor(g.d).empty());
    GuardedPage guard;
    // 300 bytes without a NUL, ending where the readable memory ends: strlen would fault.
    char* unterminated = guard.end() - 300;
    std::memset(unterminated, 'a', 300);
    // 4097 bytes without a NUL: past the bound for texts.
    char* long_text = guard.end() - 4097;
    std::memset(long_text, 'b', 4097);

    SECTION("name") {
        g.d.name = unterminated;
        CHECK(hsr::check_descriptor(g.d) == "its name does not end within 256 bytes");
    }
    SECTION("api") {
        g.d.api = unterminated;
        CHECK_THAT(hsr::check_descriptor(g.d), Catch::Contains("not an hsr plugin"));
    }
    SECTION("version") {
        g.d.version = unterminated;
        CHECK(hsr::check_descriptor(g.d) == "its version does not end within 256 bytes");
    }
    SECTION("description") {
        g.d.description = long_text;
        CHECK(hsr::check_descriptor(g.d) == "its description does not end within 4096 bytes");
    }
    SECTION("parameter name") {
        g.param.name = unterminated;
        CHECK(hsr::check_descriptor(g.d) == "its parameter #0 is malformed");
    }
    SECTION("parameter help") {
        g.param.help = long_text;
        CHECK_THAT(hsr::check_descriptor(g.d), Catch::Contains("does not end within 4096 bytes"));
    }
    SECTION("a string that ends just within the bound is fine") {
        unterminated[255] = '\0';  // 255 characters and the NUL
        g.d.name = unterminated;
        CHECK(hsr::check_descriptor(g.d).empty());
    }
}

TEST_CASE("plugin hardening: descriptor counts and sizes are bounded", "[plugin-hardening]") {
    GoodDescriptor g;
    SECTION("param_count past a one-element array that ends at an unmapped page") {
        GuardedPage guard;
        auto* last = reinterpret_cast<hsr_param_desc*>(guard.end() - sizeof(hsr_param_desc));
        *last = g.param;
        g.d.params = last;
        g.d.param_count = 257;
        CHECK(hsr::check_descriptor(g.d) == "it declares 257 parameters, more than the 256 allowed");
    }
    SECTION("a parameter element size beyond the bound") {
        g.param.struct_size = 1u << 20;
        CHECK_THAT(hsr::check_descriptor(g.d), Catch::Contains("elements of 1048576 bytes"));
    }
    SECTION("an interface table size beyond the bound") {
        g.table.struct_size = 1u << 20;
        CHECK_THAT(hsr::check_descriptor(g.d), Catch::Contains("struct_size 1048576, more than the 4096 allowed"));
    }
    SECTION("a kind outside the enum is refused before the table is read") {
        g.d.kind = 0xdeadbeef;
        g.d.interface_table = reinterpret_cast<const void*>(16);
        CHECK_THAT(hsr::check_descriptor(g.d), Catch::Contains("unknown plugin kind"));
    }
}
