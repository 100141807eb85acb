// The gooch lighting model through the hsr executable, against colours worked out by hand from the
// formula of Gooch et al. (1998): a cube whose three visible faces have known normals, lit by a
// known light and seen from a known eye, drawn by every hidden-surface algorithm; a square seen from
// behind (two-sided), with a highlight and with two lights; the parameters as `hsr plugins` lists
// them and as the host refuses them.
#include "cli_support.hpp"
#include "hsr/image.hpp"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// The paper's defaults.
struct Tones {
    double b = 0.4, y = 0.4, alpha = 0.2, beta = 0.6;
};

// colour = t k_warm + (1 - t) k_cool, t = (1 + l.n) / 2, k_cool = (0, 0, b) + alpha k_d,
// k_warm = (y, y, 0) + beta k_d; then clamped.
glm::dvec3 gooch(glm::dvec3 kd, double l_dot_n, Tones tones = {}) {
    const glm::dvec3 cool = glm::dvec3(0, 0, tones.b) + tones.alpha * kd;
    const glm::dvec3 warm = glm::dvec3(tones.y, tones.y, 0) + tones.beta * kd;
    const double t = (1 + l_dot_n) / 2;
    return glm::clamp(t * warm + (1 - t) * cool, 0.0, 1.0);
}

glm::ivec3 pixel(const hsr::Image& image, int x, int y) {
    const uint8_t* p = &image.pixels[3 * (size_t(y) * image.width + size_t(x))];
    return {p[0], p[1], p[2]};
}

// Every pixel of the 5 x 5 square around (x, y) holds the expected colour, to within the rounding
// to 8 bits.
void check_patch(const hsr::Image& image, glm::dvec2 centre, glm::dvec3 expected) {
    const int cx = int(std::floor(centre.x)), cy = int(std::floor(centre.y));
    for (int y = cy - 2; y <= cy + 2; ++y)
        for (int x = cx - 2; x <= cx + 2; ++x) {
            const glm::ivec3 got = pixel(image, x, y);
            INFO("pixel (" << x << ", " << y << "): " << got.r << " " << got.g << " " << got.b << ", expected "
                           << expected.r * 255 << " " << expected.g * 255 << " " << expected.b * 255);
            for (int k = 0; k < 3; ++k) CHECK(std::abs(got[k] - expected[k] * 255) <= 1.0);
        }
}

std::string cube_path() { return std::string(HSR_MODELS_DIR) + "/cube.obj"; }

hsr::Image render(const std::string& scene_text, const std::string& options, const std::string& tag) {
    const fs::path scene = cli::write_file(tag + ".scene", scene_text);
    const fs::path png = cli::scratch_dir() / (tag + ".png");
    fs::remove(png);
    const cli::Run r = cli::run_hsr("render " + scene.string() + " " + options + " -o " + png.string(), tag);
    INFO("hsr render " << options << "\n" << r.err);
    REQUIRE(r.status == 0);
    return hsr::read_png_rgb(png);
}

// The hidden-surface plugins `hsr plugins` lists (embree only where it is built).
std::vector<std::string> hidden_surface_algorithms() {
    const cli::Run r = cli::run_hsr("plugins", "gooch-plugins");
    REQUIRE(r.status == 0);
    std::vector<std::string> names;
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string kind, name;
        if (words >> kind >> name && kind == "hidden-surface") names.push_back(name);
    }
    return names;
}

// A 2 x 2 square in the plane z = 0, its front toward +z, in colour kd.
std::string square(glm::dvec3 kd) {
    std::ostringstream s;
    s << "polygon\n  color " << kd.r << " " << kd.g << " " << kd.b << "\n"
      << "  vertex -1 -1 0\n  vertex 1 -1 0\n  vertex 1 1 0\n  vertex -1 1 0\n"
      << "size 64 64\nbackground 0 0 0\n";
    return s.str();
}

}  // namespace

TEST_CASE("gooch: each face of a cube takes the tone of its normal, with every hidden-surface algorithm",
          "[gooch][lighting]") {
    // cube.obj spans [-1, 1]^3. Seen from (3, 4, 5) the faces +x, +y and +z face the eye; the
    // light comes from (1, 2, 3) in world space, so l.n is 1, 2 and 3 over sqrt(14) on them.
    const glm::dvec3 kd(0.2, 0.6, 0.9);
    const glm::dvec3 eye(3, 4, 5);
    const int size = 256;
    const double fov_degrees = 50;
    const std::string scene = "mesh " + cube_path() + "\n  color 0.2 0.6 0.9\n" +
                              "camera look-at eye 3 4 5 target 0 0 0 fov 50\n"
                              "light dir:1,2,3,space=world\nsize 256 256\nbackground 0 0 0\n";

    // Where each face's centre lands: the camera conventions of docs/sdk-reference.md (OpenGL view and
    // clip space, row 0 at the top).
    const glm::dmat4 view = glm::lookAt(eye, glm::dvec3(0), glm::dvec3(0, 1, 0));
    const glm::dmat4 projection = glm::perspective(glm::radians(fov_degrees), 1.0, 0.1, 100.0);
    auto window = [&](glm::dvec3 world) {
        const glm::dvec4 clip = projection * view * glm::dvec4(world, 1);
        return glm::dvec2((clip.x / clip.w + 1) / 2 * size, (1 - clip.y / clip.w) / 2 * size);
    };
    const glm::dvec3 light = glm::normalize(glm::dvec3(1, 2, 3));
    const glm::dvec3 normals[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    const std::vector<std::string> algorithms = hidden_surface_algorithms();
    REQUIRE(algorithms.size() >= 10);
    for (const std::string& algorithm : algorithms) {
        INFO("--algorithm " << algorithm);
        const hsr::Image image = render(scene, "--algorithm " + algorithm + " --lighting gooch", "cube-" + algorithm);
        REQUIRE(image.width == uint32_t(size));
        for (const glm::dvec3& n : normals) {
            INFO("face with normal " << n.x << " " << n.y << " " << n.z);
            check_patch(image, window(n), gooch(kd, glm::dot(light, n)));
        }
    }
}

TEST_CASE("gooch: the parameters b, y, alpha and beta change the tones as the formula says", "[gooch][lighting]") {
    // The +z face seen head-on, lit from the side: l.n = cos 60 degrees = 0.5.
    const glm::dvec3 kd(0.5, 0.25, 1.0);
    const std::string scene = square(kd) + "camera look-at eye 0 0 5 fov 50\nlight dir:0.8660254,0,0.5,space=world\n";
    Tones tones;
    tones.b = 0.7, tones.y = 0.1, tones.alpha = 0.5, tones.beta = 0.3;
    const hsr::Image image = render(scene, "--lighting gooch:b=0.7,y=0.1,alpha=0.5,beta=0.3", "tones");
    check_patch(image, {32, 32}, gooch(kd, 0.5, tones));
    // Everything at 1: the cool and warm colours go past 1 and are clamped.
    tones.b = tones.y = tones.alpha = tones.beta = 1;
    const hsr::Image bright = render(scene, "--lighting gooch:b=1,y=1,alpha=1,beta=1", "tones-bright");
    check_patch(bright, {32, 32}, gooch(kd, 0.5, tones));
}

TEST_CASE("gooch: a face seen from behind is lit as its front when two-sided", "[gooch][lighting]") {
    // The square faces +z; the eye is at -z, and the light is on the eye's side.
    const glm::dvec3 kd(0.2, 0.6, 0.9);
    const std::string scene = square(kd) + "camera look-at eye 0 0 -5 fov 50\nlight dir:0,0,-1,space=world\n";
    // Two-sided, the normal turns toward the eye and the light: l.n = 1, all warm.
    check_patch(render(scene, "--lighting gooch", "back-two-sided"), {32, 32}, gooch(kd, 1));
    // One-sided, the back keeps its normal, which points away from the light: l.n = -1, all cool.
    check_patch(render(scene, "--lighting gooch:two-sided=false", "back-one-sided"), {32, 32}, gooch(kd, -1));
}

TEST_CASE("gooch: a highlight adds to the tone where the light mirrors into the eye", "[gooch][lighting]") {
    // Light and eye along the normal: t = 1 (warm) everywhere, and the mirror direction r is the
    // normal, so r.v is the z of the unit vector from the point toward the eye at (0, 0, 5).
    const glm::dvec3 kd(0.2, 0.6, 0.9);
    const std::string scene = square(kd) + "camera look-at eye 0 0 5 fov 50\nlight dir:0,0,1,space=world\n";
    const glm::dvec3 warm = gooch(kd, 1);
    check_patch(render(scene, "--lighting gooch", "no-highlight"), {32, 32}, warm);
    const hsr::Image image = render(scene, "--lighting gooch:highlight=0.25", "highlight");
    const double half_width = 5 * std::tan(glm::radians(25.0));  // of the view at the square, 64 pixels
    for (int py = 28; py < 36; ++py)
        for (int px = 28; px < 36; ++px) {
            const glm::dvec3 point(((px + 0.5) / 32 - 1) * half_width, (1 - (py + 0.5) / 32) * half_width, 0);
            const double r_dot_v = glm::normalize(glm::dvec3(0, 0, 5) - point).z;
            const glm::dvec3 expected = glm::clamp(warm + 0.25 * std::pow(r_dot_v, 32), 0.0, 1.0);
            const glm::ivec3 got = pixel(image, px, py);
            INFO("pixel (" << px << ", " << py << ")");
            for (int k = 0; k < 3; ++k) CHECK(std::abs(got[k] - expected[k] * 255) <= 1.0);
        }
}

TEST_CASE("gooch: several lights blend by brightness, point lights too", "[gooch][lighting]") {
    const glm::dvec3 kd(0.2, 0.6, 0.9);
    const std::string base = square(kd) + "camera look-at eye 0 0 5 fov 50\n";
    // Front light of brightness 1 (l.n = 1), back light of brightness 3 (l.n = -1): the mean l.n
    // weighted by brightness is (1 - 3) / 4 = -0.5.
    const std::string two_lights =
        base + "light dir:0,0,1,space=world\nlight dir:0,0,-1,space=world,intensity=3\n";
    check_patch(render(two_lights, "--lighting gooch", "two-lights"), {32, 32}, gooch(kd, -0.5));
    // A white light of intensity 1 weighs as much as a grey one of colour 0.5/0.5/0.5 at intensity 2.
    const std::string grey = base + "light dir:0,0,1,space=world\nlight dir:0,0,-1,space=world,intensity=2,color=0.5/0.5/0.5\n";
    check_patch(render(grey, "--lighting gooch", "grey-light"), {32, 32}, gooch(kd, 0));
    // A point light straight in front of the square's centre: l = n there.
    const std::string point = base + "light point:0,0,2,space=world\n";
    check_patch(render(point, "--lighting gooch", "point-light"), {31.5, 31.5}, gooch(kd, 1));
}

TEST_CASE("gooch: hsr plugins lists it with its parameters, ranges and defaults", "[gooch][lighting]") {
    const cli::Run r = cli::run_hsr("plugins", "gooch-listed");
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("gooch"));
    for (const char* param : {"b=0.4 (0..1)", "y=0.4 (0..1)", "alpha=0.2 (0..1)", "beta=0.6 (0..1)",
                              "highlight=0 (0..1)", "shininess=32 (1..1000)", "two-sided=true (true|false)"})
        CHECK_THAT(r.out, Catch::Contains(param));
}

TEST_CASE("gooch: out-of-range and unknown parameters are refused with one line", "[gooch][lighting]") {
    const std::string render = "render " + cube_path() + " --width 32 --height 32 -o " +
                               (cli::scratch_dir() / "refused.png").string() + " --lighting gooch:";
    cli::require_one_line_error(cli::run_hsr(render + "alpha=1.5", "alpha"), "'alpha'");
    cli::require_one_line_error(cli::run_hsr(render + "b=-0.1", "b"), "'b'");
    cli::require_one_line_error(cli::run_hsr(render + "beta=2", "beta"), "'beta'");
    cli::require_one_line_error(cli::run_hsr(render + "y=nan", "y"), "'y'");
    cli::require_one_line_error(cli::run_hsr(render + "shininess=0", "shininess"), "'shininess'");
    cli::require_one_line_error(cli::run_hsr(render + "highlight=1.01", "highlight"), "'highlight'");
    cli::require_one_line_error(cli::run_hsr(render + "gamma=1", "unknown"), "gamma");
}

TEST_CASE("gooch: an instanced scene is shaded like the mesh it repeats", "[gooch][lighting]") {
    // Three cubes side by side (instances of one mesh, no rotation), head-on with the light from the
    // eye: the front faces have l.n = 1 and are all warm.
    const glm::dvec3 kd(0.2, 0.6, 0.9);
    const std::string scene = "mesh " + cube_path() + "\n  color 0.2 0.6 0.9\nrepeat 3 1 1\n"
                              "camera orbit\nlight dir:0,0,1,space=world\nsize 192 64\nbackground 0 0 0\n";
    const hsr::Image image = render(scene, "--lighting gooch --ortho", "instanced");
    const glm::dvec3 warm = gooch(kd, 1);
    int warm_pixels = 0, other = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const glm::ivec3 p = pixel(image, int(x), int(y));
            if (p == glm::ivec3(0)) continue;
            bool is_warm = true;
            for (int k = 0; k < 3; ++k) is_warm = is_warm && std::abs(p[k] - warm[k] * 255) <= 1.0;
            ++(is_warm ? warm_pixels : other);
        }
    CHECK(warm_pixels > 3 * 100);
    CHECK(other == 0);
}
