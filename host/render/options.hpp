// The options of hsr render as the command line gave them (render.cpp parses them), and what the
// other steps read of them directly.
#pragma once

#include "common/options.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace hsr::host {

// The options of hsr render as the command line gave them, not yet checked.
struct RenderOptions {
    bool help = false;
    std::string jobs;  // --jobs FILE
    std::vector<std::string> models;  // every MODEL of the command line
    std::string model;                // the MODEL of this render: the first of models
    std::string output;
    std::string algorithm = default_algorithm;
    std::string lighting = default_lighting;
    std::vector<std::string> lights;
    std::vector<std::string> plugin_dirs;
    std::vector<std::string> limits;  // NAME=N (limits.hpp)
    std::string background = default_background;
    std::string color;
    std::string line_color;     // hidden-line plugins; empty: contrasting with the background
    double line_width = 1.0;    // hidden-line plugins: pixels
    int64_t samples = 1;        // supersampling (signed, so that a negative number is refused)
    std::string depth_out;      // .png (greyscale), .npy, .pfm or .exr (camera-space distance)
    std::string id_out;         // .npy or .png (16-bit RGBA): object, face, instance per pixel
    std::string normal_out;     // .npy, .pfm, .exr or .png: camera-space face normals
    std::string format;         // --format of a MODEL '-' read from standard input
    std::string overdraw_out;
    std::string depth_tests_out;
    std::string repeat;
    std::string edges = "features";
    std::string hidden_lines = "hidden";
    std::string trace;
    std::string surface, range, heightmap;
    int64_t random_triangles = 0;  // --random-triangles N; signed, so that a negative count is refused
    std::string seed = "1";        // --seed S
    double heightmap_height = 0.0;
    float repeat_gap = 0.25f, repeat_jitter = 0.0f;
    std::string yaw_text = "0", pitch_text = "0";  // --yaw and --pitch: degrees, or A:B:STEP (frames.hpp)
    int64_t views = 1;                              // --views N: a turntable (signed, so that -1 is refused)
    float yaw = 0, pitch = 0;  // this frame's (plan_frames, frames.hpp)
    double yaw_turn = 0;       // this frame's turn of the turntable, degrees added to the yaw
    float zoom = 1, crease_angle = 40, fov = 35;
    std::string eye, target, up;  // x,y,z each: a look-at camera
    std::string camera;           // --camera NAME|INDEX: a camera of the model file (glTF)
    std::vector<std::string> clip_planes;  // --clip-plane a,b,c,d (repeatable)
    std::vector<float> sections;           // --section z (repeatable)
    float near_plane = 0;                  // --near, when given
    float opacity = 1;                     // --opacity of a single model
    bool orthographic = false;
    bool stats = false;
    int64_t threads = 0;  // signed, so that a negative number is refused rather than wrapped
    int64_t step = 0;     // the step a frame stops after (0: --step not given); set from step_text
    std::string step_text;  // --step N or A..B
    int64_t width = 1024, height = 1024;
    // The options named on the command line, as opposed to left at their defaults.
    std::set<std::string> given;

    bool was_given(const std::string& option) const { return given.count(option) > 0; }
};

// The options of args, parsed but not checked; malformed options and values of the wrong type are
// boost::program_options errors, an unknown option a UsageError.
RenderOptions parse_render_options(const std::vector<std::string>& args);

// A --jobs line's words as the render's command line: the files the line reads (MODEL, --heightmap,
// --plugin-path), when relative, taken from `folder`, the jobs file's; then every option of
// `defaults` (the command line of hsr render --jobs, whose --jobs is left out) that the line does
// not give itself. The files the line writes stay relative to the current folder.
std::vector<std::string> job_line_arguments(const std::vector<std::string>& line, const std::filesystem::path& folder,
                                            const std::vector<std::string>& defaults);

// The placeholder an output name may hold for the model's file name without its extension.
inline constexpr std::string_view stem_placeholder = "{stem}";
// text with every {stem} replaced by the stem of the options' model (model_path), its % signs
// doubled, as a frame-number template (OutputTemplate) reads them.
std::string with_model_stem(const std::string& text, const RenderOptions& options);
// The options, then every plugin found with its parameters.
void print_render_help(const std::vector<std::string>& plugin_dirs);

// The sections and clip planes the command line asks for, to add after a .scene file's.
void add_clip_plane_options(const RenderOptions& options, std::vector<glm::vec4>& planes);

// The formats --format accepts for a model read from standard input (MODEL '-').
inline constexpr const char* stdin_model_formats[] = {"obj", "off", "ply", "stl", "gltf", "glb"};
// "obj, off, ply, stl, gltf or glb", for messages.
std::string stdin_model_format_list();

// With --background none the picture has an alpha channel instead of a background colour.
inline bool transparent_background(const RenderOptions& options) { return options.background == "none"; }

// The file the scene comes from: MODEL, or --heightmap's PNG, or "surface" for --surface, or
// "random-triangles" for --random-triangles, or "stdin" for MODEL '-'. Its stem names the default
// output.
std::filesystem::path model_path(const RenderOptions& options);

}  // namespace hsr::host
