// Many frames from one hsr render (docs/many-frames.md), through the executable: --views and angle
// ranges give the frames that single renders at those angles give, byte for byte; frame-number
// templates name the files; a --jobs file runs its lines, loading each model once, and its mistakes
// name FILE:LINE before anything is rendered.
#include "cli_support.hpp"
#include "render/jobs.hpp"
#include "render/options.hpp"

#include "hsr/error.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sys/stat.h>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using cli::Run;
using cli::require_one_line_error;
using cli::run_hsr;
using cli::slurp;

std::string model(const char* name) { return std::string(HSR_MODELS_DIR) + "/" + name; }

// An empty folder of its own in the scratch folder.
fs::path fresh_dir(const std::string& name) {
    const fs::path dir = cli::scratch_dir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// The files of a folder, by name.
std::vector<std::string> names_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::size_t count_of(const std::string& text, const std::string& part) {
    std::size_t count = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
    return count;
}

// A single render of the monkey at this yaw and pitch, to compare a frame with.
std::string single_render(const fs::path& dir, const std::string& options, const std::string& angles) {
    const fs::path picture = dir / "single.png";
    const Run r = run_hsr("render " + model("monkey.obj") + " " + options + " " + angles + " -o " + picture.string(),
                          "single");
    INFO(angles << ": " << r.err);
    REQUIRE(r.status == 0);
    return slurp(picture);
}

const std::string small = "--width 96 --height 80";

}  // namespace

TEST_CASE("frames: --views N writes N frames, each the single render at its yaw", "[frames]") {
    const fs::path dir = fresh_dir("views");
    const Run r = run_hsr("render " + model("monkey.obj") + " " + small + " --views 8 --yaw 10 -o " +
                              (dir / "turn-%03d.png").string(), "views");
    INFO(r.err);
    REQUIRE(r.status == 0);
    std::vector<std::string> expected;
    for (int k = 0; k < 8; ++k) expected.push_back(fmt::format("turn-{:03}.png", k));
    CHECK(names_in(dir) == expected);
    CHECK(count_of(r.err, "wrote ") == 8);
    const fs::path singles = fresh_dir("views-single");
    for (int k = 0; k < 8; ++k) {
        INFO("frame " << k);
        // 10 + 45 k degrees: 360 / 8 apart from --yaw.
        CHECK(slurp(dir / expected[std::size_t(k)]) ==
              single_render(singles, small, "--yaw " + std::to_string(10 + 45 * k)));
    }
    // Different frames are different pictures.
    CHECK(slurp(dir / expected[0]) != slurp(dir / expected[1]));
}

TEST_CASE("frames: --yaw and --pitch ranges, inclusive of B when a step lands on it", "[frames]") {
    const fs::path dir = fresh_dir("ranges");
    // Yaw 90, 60, 30, 0 (a negative step, landing on B); pitch -20, 5 (25 further is past 20).
    const Run r = run_hsr("render " + model("monkey.obj") + " " + small + " --yaw 90:0:-30 --pitch -20:20:25 -o " +
                              (dir / "f%d.png").string() + " --depth-out " + (dir / "d%02d.png").string(), "ranges");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(names_in(dir) == std::vector<std::string>{"d00.png", "d01.png", "d02.png", "d03.png", "d04.png", "d05.png",
                                                    "d06.png", "d07.png", "f0.png", "f1.png", "f2.png", "f3.png",
                                                    "f4.png", "f5.png", "f6.png", "f7.png"});
    const fs::path singles = fresh_dir("ranges-single");
    int frame = 0;
    for (int pitch : {-20, 5})  // the pitches outermost
        for (int yaw : {90, 60, 30, 0}) {
            INFO("frame " << frame << ": yaw " << yaw << ", pitch " << pitch);
            CHECK(slurp(dir / fmt::format("f{}.png", frame)) ==
                  single_render(singles, small, fmt::format("--yaw {} --pitch {}", yaw, pitch)));
            ++frame;
        }
    // A range of one value is one frame, which needs no number in its name.
    const fs::path one = dir / "one.png";
    const Run single = run_hsr("render " + model("monkey.obj") + " " + small + " --yaw 30:30:5 -o " + one.string(),
                               "range-of-one");
    INFO(single.err);
    CHECK(single.status == 0);
    CHECK(slurp(one) == single_render(singles, small, "--yaw 30"));
}

TEST_CASE("frames: a hidden-line plugin's frames, each with its numbered trace", "[frames][lines]") {
    const fs::path dir = fresh_dir("line-frames");
    const std::string cube = "render " + model("cube.obj") + " -a appel --width 64 --height 64 --pitch 20 ";
    const Run r = run_hsr(cube + "--yaw 0:90:45 -o " + (dir / "l-%d.svg").string() + " --trace " +
                              (dir / "t-%d.jsonl").string(), "line-frames");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(names_in(dir) ==
          std::vector<std::string>{"l-0.svg", "l-1.svg", "l-2.svg", "t-0.jsonl", "t-1.jsonl", "t-2.jsonl"});
    const fs::path single = fresh_dir("line-frames-single");
    const Run one = run_hsr(cube + "--yaw 45 -o " + (single / "l.svg").string() + " --trace " +
                                (single / "t.jsonl").string(), "line-frames-single");
    REQUIRE(one.status == 0);
    // Cairo numbers the drawings of a process (id="surface<n>"); the rest is the same.
    const auto drawing = [](const fs::path& svg) {
        return std::regex_replace(slurp(svg), std::regex("id=\"surface[0-9]+\""), "id=\"surface\"");
    };
    CHECK(drawing(dir / "l-1.svg") == drawing(single / "l.svg"));
    CHECK(slurp(dir / "t-1.jsonl") == slurp(single / "t.jsonl"));
    CHECK(slurp(dir / "l-0.svg") != slurp(dir / "l-1.svg"));
}

TEST_CASE("frames: output templates, their mistakes, and the default name of several frames", "[frames]") {
    const fs::path dir = fresh_dir("templates");
    const std::string cube = "render " + model("cube.obj") + " --width 32 --height 32 ";
    CHECK(run_hsr(cube + "--views 3 -o " + (dir / "a-%d-100%%.png").string(), "percent").status == 0);
    CHECK(run_hsr(cube + "--views 2 -o " + (dir / "b%4d.png").string(), "width").status == 0);
    // One frame: a template still names it, frame 0; %% is a % sign.
    CHECK(run_hsr(cube + "-o " + (dir / "c%03d.png").string(), "one-frame").status == 0);
    CHECK(run_hsr(cube + "-o " + (dir / "100%%.png").string(), "literal").status == 0);
    CHECK(names_in(dir) == std::vector<std::string>{"100%.png", "a-0-100%.png", "a-1-100%.png", "a-2-100%.png",
                                                    "b   0.png", "b   1.png", "c000.png"});
    // Without -o, several frames are <model name>-000.png, ... in the current folder.
    const std::string command = "cd " + dir.string() + " && " + HSR_BINARY_DIR + "/hsr render " + model("cube.obj") +
                                " --width 16 --height 16 --views 2 2> /dev/null";
    CHECK(std::system(command.c_str()) == 0);
    CHECK(fs::exists(dir / "cube-000.png"));
    CHECK(fs::exists(dir / "cube-001.png"));

    const fs::path none = fresh_dir("templates-refused");
    require_one_line_error(run_hsr(cube + "--views 3 -o " + (none / "x.png").string(), "no-number"),
                           "3 frames need a frame number in the name, e.g. 'x-%03d.png'");
    require_one_line_error(run_hsr(cube + "--yaw 0:20:10 -o " + (none / "x%d.png").string() + " --depth-out " +
                                       (none / "d.png").string(), "no-number-depth"),
                           "--depth-out");
    for (const char* bad : {"x%.png", "x%s.png", "x%-3d.png", "x%+d.png", "x%99d.png"})
        require_one_line_error(run_hsr(cube + "-o " + (none / bad).string(), "bad-template"),
                               "write %% for a % sign");
    require_one_line_error(run_hsr(cube + "--views 2 -o " + (none / "x%d-%d.png").string(), "two-numbers"),
                           "one frame number (%d) in a name, not two");
    // Two frames' files that are the same file: frame 10 of a%d is frame 0 of a1%d.
    require_one_line_error(run_hsr(cube + "--views 12 -o " + (none / "a%d.png").string() + " --depth-out " +
                                       (none / "a1%d.png").string(), "collide"),
                           "name the same file");
    CHECK(names_in(none).empty());
}

TEST_CASE("frames: --views and ranges refuse what makes no frames or too many", "[frames]") {
    const std::string cube = "render " + model("cube.obj") + " --width 16 --height 16 -o x-%d.png ";
    require_one_line_error(run_hsr(cube + "--views 0", "views-0"), "--views 0");
    require_one_line_error(run_hsr(cube + "--yaw 0:10:0", "step-0"), "the step must not be 0");
    require_one_line_error(run_hsr(cube + "--yaw 0:10:-5", "away"), "never reaches 10");
    require_one_line_error(run_hsr(cube + "--pitch 0:inf:1", "inf"), "three finite numbers");
    require_one_line_error(run_hsr(cube + "--views 200000", "views-limit"), "--limit frames=N");
    require_one_line_error(run_hsr(cube + "--yaw 0:360:1 --views 300", "views-range"), "--views or a --yaw range");
    require_one_line_error(run_hsr(cube + "--yaw 0:1:1e-9", "range-limit"), "over the limit of 100000");
    // The limit can be raised like any other.
    require_one_line_error(run_hsr(cube + "--views 20 --limit frames=10", "limit-lowered"),
                           "20 frames, over the limit of 10");
}

TEST_CASE("frames: a --jobs file loads each model once and renders every line as its command line would",
          "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs");
    const std::string monkey = model("monkey.obj"), cube = model("cube.obj");
    const fs::path jobs = dir / "three.jobs";
    std::ofstream(jobs) << "# comments and blank lines are skipped\n\n"
                        << "   # indented too\n"
                        << monkey << " " << small << " --views 2 -o " << (dir / "m-%d.png").string() << "\n"
                        << cube << " --width 40 --height 40 -a painter -l lambert -o '" << (dir / "cube one.png").string()
                        << "'\n"
                        // The same file by another path: the same load.
                        << HSR_MODELS_DIR << "/../models/monkey.obj " << small
                        << " -a scanline-zbuffer -l phong:interpolation=gouraud --yaw 45 -o "
                        << (dir / "m-scanline.png").string() << "\n"
                        << monkey << " --width 64 --height 64 -a appel --hidden dashed -o " << (dir / "m.svg").string()
                        << "\n";
    const Run r = run_hsr("render --jobs " + jobs.string(), "jobs");
    INFO(r.err);
    REQUIRE(r.status == 0);
    // Loaded once for its three lines (a hidden-line plugin's too), the cube once.
    CHECK(count_of(r.err, "loaded ") == 2);
    CHECK_THAT(r.err, Catch::Contains("loaded " + monkey + " once for 3 jobs"));
    CHECK_THAT(r.err, Catch::Contains("loaded " + cube + " once for 1 job "));
    CHECK(names_in(dir) ==
          std::vector<std::string>{"cube one.png", "m-0.png", "m-1.png", "m-scanline.png", "m.svg", "three.jobs"});

    // Each file is what the same options on a command line write.
    const fs::path singles = fresh_dir("jobs-single");
    CHECK(slurp(dir / "m-1.png") == single_render(singles, small, "--yaw 180"));
    CHECK(slurp(dir / "m-scanline.png") ==
          single_render(singles, small + " -a scanline-zbuffer -l phong:interpolation=gouraud", "--yaw 45"));
    const Run painter = run_hsr("render " + cube + " --width 40 --height 40 -a painter -l lambert -o " +
                                    (singles / "cube.png").string(), "jobs-painter");
    REQUIRE(painter.status == 0);
    CHECK(slurp(dir / "cube one.png") == slurp(singles / "cube.png"));
    const Run lines = run_hsr("render " + monkey + " --width 64 --height 64 -a appel --hidden dashed -o " +
                                  (singles / "m.svg").string(), "jobs-lines");
    REQUIRE(lines.status == 0);
    CHECK(slurp(dir / "m.svg") == slurp(singles / "m.svg"));
}

TEST_CASE("frames: a mistake on any line of a --jobs file stops the run before it renders, naming FILE:LINE",
          "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs-mistakes");
    const std::string cube = model("cube.obj") + " --width 16 --height 16 -o " + dir.string();
    const auto jobs_error = [&](const std::string& name, const std::string& text, const std::string& expected) {
        const fs::path file = dir / name;
        std::ofstream(file) << text;
        INFO(text);
        require_one_line_error(run_hsr("render --jobs " + file.string(), name), file.string() + ":" + expected);
        fs::remove(file);
        CHECK(names_in(dir).empty());
    };
    jobs_error("option.jobs", cube + "/a.png\n\n" + cube + "/b.png --no-such-option\n", "3: ");
    jobs_error("plugin.jobs", "# first\n" + cube + "/a.png\n" + cube + "/b.png -a no-such-plugin\n",
               "3: no hidden-surface or hidden-line plugin named 'no-such-plugin'");
    jobs_error("template.jobs", cube + "/a.png --views 2\n", "1: --output '");
    jobs_error("twice.jobs", cube + "/a.png\n" + cube + "/b.png\n" + cube + "/a.png --yaw 10\n",
               "3: '" + (dir / "a.png").string() + "' is written by " + (dir / "twice.jobs").string() + ":1 too");
    jobs_error("nested.jobs", cube + "/a.png --jobs other.jobs\n", "1: --jobs: a job cannot run another jobs file");
    jobs_error("color.jobs", cube + "/a.png --color 'not a colour'\n", "1: --color: 'not a colour' is not a colour");
    jobs_error("limit.jobs", cube + "/a-%d.png --views 6\n" + cube + "/b-%d.png --views 5 --limit frames=10\n",
               "2: the lines so far: 11 frames, over the limit of 10");

    const fs::path empty = dir / "empty.jobs";
    std::ofstream(empty) << "# nothing but comments\n\n";
    require_one_line_error(run_hsr("render --jobs " + empty.string(), "empty-jobs"), "no jobs in the file");
    fs::remove(empty);
    // The models go on the lines; a mistyped option beside --jobs is refused before the file is read.
    require_one_line_error(run_hsr("render --jobs x.jobs cube.obj", "jobs-and-model"),
                           "--jobs x.jobs: the models go on the lines of the file ('cube.obj' is on the command line)");
    require_one_line_error(run_hsr("render --jobs x.jobs --widht 10", "jobs-typo"),
                           "unknown option --widht (did you mean --width?) (see hsr render --help)");
    require_one_line_error(run_hsr("render --jobs /nonexistent/x.jobs", "jobs-missing"), "cannot read it");
}

TEST_CASE("frames: a --jobs line that fails while running is reported, and the others still run", "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs-failing");
    const fs::path broken = dir / "broken.off";
    std::ofstream(broken) << "OFF\nthis is not a mesh\n";
    const fs::path jobs = dir / "failing.jobs";
    const std::string options = " --width 16 --height 16 -o " + dir.string();
    std::ofstream(jobs) << broken.string() << options << "/a.png\n"
                        << model("cube.obj") << options << "/b.png\n"
                        << broken.string() << options << "/c.png --yaw 5\n";
    const Run r = run_hsr("render --jobs " + jobs.string(), "jobs-failing");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::Contains("hsr: error: " + jobs.string() + ":1: "));
    CHECK_THAT(r.err, Catch::Contains("hsr: error: " + jobs.string() + ":3: "));
    CHECK_THAT(r.err, Catch::EndsWith("hsr: error: 2 of 3 jobs failed (the errors above)\n"));
    CHECK(names_in(dir) == std::vector<std::string>{"b.png", "broken.off", "failing.jobs"});
}

TEST_CASE("frames: the example job file of docs/many-frames.md runs and writes every file it names",
          "[frames][jobs]") {
    const fs::path dir = fresh_dir("example-jobs");
    const fs::path err = dir / "stderr.txt";
    // Run from a folder of its own: the models are found from the file's folder, the files are
    // written into the current one.
    const std::string command = "cd " + dir.string() + " && " + HSR_BINARY_DIR + "/hsr render --jobs " +
                                HSR_SOURCE_DIR + "/docs/examples/turntable.jobs 2> " + err.string();
    const int status = std::system(command.c_str());
    INFO(slurp(err));
    REQUIRE(status == 0);
    CHECK_THAT(slurp(err), Catch::Contains("loaded " + (fs::path(HSR_SOURCE_DIR) / "models/bunny.obj").string() +
                                           " once for 2 jobs"));
    std::vector<std::string> expected{"boxes-0.svg", "boxes-1.svg", "boxes-2.svg", "bunny-painter.png"};
    for (int k = 0; k < 12; ++k) expected.push_back(fmt::format("bunny-turn-{:02}.png", k));
    for (int k = 0; k < 5; ++k) expected.push_back(fmt::format("monkey-{}.png", k));
    for (int k = 0; k < 5; ++k) expected.push_back(fmt::format("monkey-depth-{}.png", k));
    expected.push_back("stderr.txt");
    std::sort(expected.begin(), expected.end());
    CHECK(names_in(dir) == expected);
}

TEST_CASE("frames: a --jobs line is split and unquoted as a shell does it", "[frames][jobs]") {
    using hsr::host::split_job_line;
    using Words = std::vector<std::string>;
    CHECK(split_job_line("") == Words{});
    CHECK(split_job_line(" \t ") == Words{});
    CHECK(split_job_line("a  b\tc") == Words{"a", "b", "c"});
    CHECK(split_job_line("'b c' x'y'z ''") == Words{"b c", "xyz", ""});
    CHECK(split_job_line("'a\\b' 'it\"s'") == Words{"a\\b", "it\"s"});  // nothing is special in '...'
    CHECK(split_job_line("\"d\\\"e\" \"\\$\\`\\\\\" \"a\\b\"") == Words{"d\"e", "$`\\", "a\\b"});
    CHECK(split_job_line("f\\ g \\'h") == Words{"f g", "'h"});
    CHECK(split_job_line("-o \"out put.png\"") == Words{"-o", "out put.png"});
    CHECK_THROWS_WITH(split_job_line("a \"b"), "a quote (\") at column 3 is not closed on its line");
    CHECK_THROWS_WITH(split_job_line("'"), "a quote (') at column 1 is not closed on its line");
    CHECK_THROWS_WITH(split_job_line("a \\"), "the line ends in a backslash, which escapes nothing");
    CHECK_THROWS_AS(split_job_line("\"a'"), hsr::UsageError);
}

TEST_CASE("frames: a --jobs file with CR LF line ends runs", "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs-crlf");
    const std::string cube = model("cube.obj") + " --width 16 --height 16 -o " + dir.string();
    const fs::path jobs = dir / "crlf.jobs";
    std::ofstream(jobs, std::ios::binary) << "# made on another system\r\n" << cube << "/a.png\r\n\r\n" << cube
                                          << "/\"b c.png\"\r\n";
    const Run r = run_hsr("render --jobs " + jobs.string(), "jobs-crlf");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(names_in(dir) == std::vector<std::string>{"a.png", "b c.png", "crlf.jobs"});
}

TEST_CASE("frames: --jobs refuses what is not a file of renders before reading it", "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs-refused");
    const std::string cube = model("cube.obj") + " --width 16 --height 16 -o " + dir.string();
    // A FIFO would wait for a writer for ever, /dev/zero be read until memory runs out.
    const fs::path fifo = dir / "fifo.jobs";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    require_one_line_error(run_hsr("render --jobs " + fifo.string(), "jobs-fifo", 20),
                           "fifo.jobs': is not a regular file (a pipe, device or socket), not a file of renders");
    require_one_line_error(run_hsr("render --jobs /dev/zero", "jobs-zero", 20),
                           "--jobs '/dev/zero': is not a regular file");
    require_one_line_error(run_hsr("render --jobs " + dir.string(), "jobs-folder"), "is a folder, not a file of renders");

    const auto jobs_error = [&](const std::string& name, const std::string& text, const std::string& expected) {
        const fs::path file = dir / name;
        std::ofstream(file, std::ios::binary) << text;
        require_one_line_error(run_hsr("render --jobs " + file.string(), name), file.string() + ":" + expected);
    };
    jobs_error("quote.jobs", cube + "/a.png\n" + cube + "/\"b.png\n", "2: a quote (\") at column ");
    jobs_error("long.jobs", cube + "/a.png\n# " + std::string(70000, 'x') + "\n",
               "2: the line is longer than a jobs line may be (65536 bytes)");
    std::string words = cube + "/w.png";
    for (int k = 0; k < 2100; ++k) words += " --yaw 1";
    jobs_error("words.jobs", words + "\n", "1: 4207 arguments, more than a command may have (4096)");
    CHECK(names_in(dir) == std::vector<std::string>{"fifo.jobs", "long.jobs", "quote.jobs", "words.jobs"});
}

TEST_CASE("frames: a --jobs line reads its files from the jobs file's folder and writes into the current one",
          "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs-folders");
    const fs::path models = dir / "models", work = dir / "work";
    fs::create_directories(models / "sub");
    fs::create_directories(work);
    fs::copy_file(model("cube.obj"), models / "cube.obj");
    fs::copy_file(model("pyramid.stl"), models / "sub" / "pyramid.stl");
    std::ofstream(models / "relative.jobs") << "cube.obj --width 20 --height 20 -o cube.png\n"
                                            << "sub/pyramid.stl --width 20 --height 20\n"
                                            << model("octahedron.ply") << " --width 20 --height 20\n";
    const Run r = run_hsr("render --jobs ../models/relative.jobs", "jobs-folders", 60, work);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.err, Catch::Contains("loaded ../models/cube.obj once"));
    CHECK_THAT(r.err, Catch::Contains("loaded ../models/sub/pyramid.stl once"));
    CHECK(names_in(work) == std::vector<std::string>{"cube.png", "octahedron.png", "pyramid.png"});
    CHECK(names_in(models) == std::vector<std::string>{"cube.obj", "relative.jobs", "sub"});
}

TEST_CASE("frames: options after --jobs FILE go to every line that does not give them", "[frames][jobs]") {
    const fs::path dir = fresh_dir("jobs-defaults");
    const std::string cube = model("cube.obj");
    const fs::path jobs = dir / "defaults.jobs";
    std::ofstream(jobs) << cube << " -o " << (dir / "small.png").string() << "\n"
                        << cube << " --width 40 -a painter -o " << (dir / "wide.png").string() << "\n";
    const Run r = run_hsr("render --jobs " + jobs.string() + " --width 24 --height 16 -l lambert", "jobs-defaults");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.err, Catch::Contains("small.png (24x16,"));
    CHECK_THAT(r.err, Catch::Contains("wide.png (40x16,"));
    // Each is what its line with the command line's other options writes alone.
    const Run alone = run_hsr("render " + cube + " --width 40 --height 16 -a painter -l lambert -o " +
                                  (dir / "alone.png").string(), "jobs-defaults-alone");
    REQUIRE(alone.status == 0);
    CHECK(slurp(dir / "wide.png") == slurp(dir / "alone.png"));
}

TEST_CASE("frames: the words of a --jobs line as its render's command line", "[frames][jobs]") {
    using hsr::host::job_line_arguments;
    using Words = std::vector<std::string>;
    CHECK(job_line_arguments({"cube.obj", "-o", "x.png"}, "", {}) == Words{"cube.obj", "-o", "x.png"});
    CHECK(job_line_arguments({"cube.obj", "-o", "x.png"}, "jobs/here", {}) ==
          Words{"--model=jobs/here/cube.obj", "-o", "x.png"});
    CHECK(job_line_arguments({"../m/cube.obj", "--heightmap=h.png", "--plugin-path", "p"}, "a/b", {}) ==
          Words{"--model=a/m/cube.obj", "--heightmap=a/b/h.png", "--plugin-path=a/b/p"});
    CHECK(job_line_arguments({"/abs/cube.obj", "--trace", "t.jsonl"}, "a", {}) == Words{"/abs/cube.obj", "--trace", "t.jsonl"});
    CHECK(job_line_arguments({"cube.obj", "--width", "8"}, "", {"--jobs", "f.jobs", "--width=64", "--height", "32",
                                                                 "--ortho", "--light", "dir:0,0,1"}) ==
          Words{"cube.obj", "--width", "8", "--height", "32", "--ortho", "--light", "dir:0,0,1"});
    // A repeatable option on the line replaces the command line's.
    CHECK(job_line_arguments({"cube.obj", "--light", "dir:1,0,0"}, "", {"--light", "dir:0,0,1", "--light", "dir:0,1,0"}) ==
          Words{"cube.obj", "--light", "dir:1,0,0"});
    CHECK_THROWS_WITH(job_line_arguments({"cube.obj", "--algoritm", "zbuffer"}, "", {}),
                      Catch::Contains("unknown option --algoritm (did you mean --algorithm?)"));
}
