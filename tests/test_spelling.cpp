// The suggestions of "(did you mean ...?)" (hsr/spelling.hpp): edit distances worked out by hand,
// and which slips are near enough to suggest a word.
#include "hsr/spelling.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

TEST_CASE("spelling: edit distance counts insertions, deletions, substitutions and swaps", "[spelling]") {
    CHECK(hsr::edit_distance("", "") == 0);
    CHECK(hsr::edit_distance("", "abc") == 3);
    CHECK(hsr::edit_distance("abc", "") == 3);
    CHECK(hsr::edit_distance("width", "width") == 0);
    CHECK(hsr::edit_distance("algoritm", "algorithm") == 1);  // an insertion
    CHECK(hsr::edit_distance("zbuffer", "zbufer") == 1);      // a deletion
    CHECK(hsr::edit_distance("render", "rendor") == 1);       // a substitution
    CHECK(hsr::edit_distance("widht", "width") == 1);         // two neighbours swapped
    CHECK(hsr::edit_distance("kitten", "sitting") == 3);
    CHECK(hsr::edit_distance("ca", "abc") == 3);              // optimal string alignment: no edit of a swapped pair
    CHECK(hsr::edit_distance("Phong", "phong") == 0);         // letters without case
}

TEST_CASE("spelling: the closest known word, when near enough to be a slip", "[spelling]") {
    const std::vector<std::string> commands{"render", "plugins", "bench", "view"};
    CHECK(hsr::closest_spelling("rendr", commands) == "render");
    CHECK(hsr::closest_spelling("veiw", commands) == "view");
    CHECK(hsr::closest_spelling("plugin", commands) == "plugins");
    CHECK_FALSE(hsr::closest_spelling("render", commands));  // known: nothing to suggest
    CHECK_FALSE(hsr::closest_spelling("draw", commands));
    CHECK_FALSE(hsr::closest_spelling("", commands));
    CHECK_FALSE(hsr::closest_spelling("rendr", {}));

    const std::vector<std::string> plugins{"zbuffer", "scanline-zbuffer", "hierarchical-zbuffer", "painter", "bsp"};
    CHECK(hsr::closest_spelling("zbufer", plugins) == "zbuffer");
    CHECK(hsr::closest_spelling("scanline-zbufer", plugins) == "scanline-zbuffer");
    CHECK(hsr::closest_spelling("paitner", plugins) == "painter");
    CHECK(hsr::closest_spelling("bps", plugins) == "bsp");
    // Up to 5 characters one edit, up to 8 two, beyond that three.
    CHECK_FALSE(hsr::closest_spelling("bxx", plugins));
    CHECK(hsr::closest_spelling("pinter", plugins) == "painter");
    CHECK(hsr::closest_spelling("pointr", plugins) == "painter");
    CHECK_FALSE(hsr::closest_spelling("pontrr", plugins));
    CHECK(hsr::closest_spelling("hierarchcal-zbufer", plugins) == "hierarchical-zbuffer");

    // The first of equally near words.
    CHECK(hsr::closest_spelling("ab", {"ac", "ad"}) == "ac");
}

TEST_CASE("spelling: did you mean, or nothing", "[spelling]") {
    const std::vector<std::string> options{"algorithm", "lighting", "width", "height"};
    CHECK(hsr::did_you_mean("algoritm", options) == " (did you mean algorithm?)");
    CHECK(hsr::did_you_mean("heigth", options) == " (did you mean height?)");
    CHECK(hsr::did_you_mean("colour", options).empty());
}
