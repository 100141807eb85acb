// Host-side parameter handling: parsing "name:key=value,..." and validating against a schema.
#include "hsr/error.hpp"
#include "hsr/params.hpp"

#include <catch2/catch.hpp>

namespace {

const hsr_param_desc schema[] = {
    {sizeof(hsr_param_desc), "cull", HSR_PARAM_BOOL, "false", 0, 1, nullptr, "b"},
    {sizeof(hsr_param_desc), "depth", HSR_PARAM_INT, "4", 1, 8, nullptr, "i"},
    {sizeof(hsr_param_desc), "shininess", HSR_PARAM_FLOAT, "32", 1, 1000, nullptr, "f"},
    {sizeof(hsr_param_desc), "test", HSR_PARAM_ENUM, "less", 0, 0, "less|greater", "e"},
    {sizeof(hsr_param_desc), "tint", HSR_PARAM_COLOR, "1/0.5/0", 0, 1, nullptr, "c"},
};

hsr_plugin_descriptor make_descriptor() {
    hsr_plugin_descriptor d{};
    d.struct_size = sizeof d;
    d.name = "demo";
    d.params = schema;
    d.param_count = 5;
    return d;
}

}  // namespace

TEST_CASE("plugin specs split into a name and key=value settings", "[params]") {
    auto spec = hsr::parse_plugin_spec("zbuffer");
    CHECK(spec.name == "zbuffer");
    CHECK(spec.settings.empty());
    spec = hsr::parse_plugin_spec("phong:shininess=10, interpolation=gouraud,specular-color=1/0/0");
    CHECK(spec.name == "phong");
    REQUIRE(spec.settings.size() == 3);
    CHECK(spec.settings[1] == hsr::Setting{"interpolation", "gouraud"});
    CHECK(spec.settings[2] == hsr::Setting{"specular-color", "1/0/0"});
    CHECK_THROWS_WITH(hsr::parse_plugin_spec("phong:shininess"), Catch::Contains("not key=value"));
    CHECK_THROWS_WITH(hsr::parse_plugin_spec(":a=b"), Catch::Contains("plugin name missing"));
}

TEST_CASE("defaults fill every parameter, in schema order", "[params]") {
    const hsr_plugin_descriptor d = make_descriptor();
    hsr::ParamValues v = hsr::resolve_params(d, {});
    REQUIRE(v.size() == 5);
    CHECK(v.values()[0].number == 0);
    CHECK(v.values()[1].number == 4);
    CHECK(v.values()[2].number == 32);
    CHECK(v.values()[3].number == 0);
    CHECK(v.values()[4].color[0] == 1.0f);
    CHECK(v.values()[4].color[1] == 0.5f);
    CHECK(v.values()[4].color[2] == 0.0f);
}

TEST_CASE("user values are parsed by type", "[params]") {
    const hsr_plugin_descriptor d = make_descriptor();
    hsr::ParamValues v = hsr::resolve_params(
        d, {{"cull", "yes"}, {"depth", "8"}, {"shininess", "2.5"}, {"test", "greater"}, {"tint", "#ff8000"}});
    CHECK(v.values()[0].number == 1);
    CHECK(v.values()[1].number == 8);
    CHECK(v.values()[2].number == 2.5);
    CHECK(v.values()[3].number == 1);
    CHECK(v.values()[4].color[1] == Approx(128.0 / 255.0));
}

TEST_CASE("a number may carry a plus sign", "[params]") {
    const hsr_plugin_descriptor d = make_descriptor();
    CHECK(hsr::resolve_params(d, {{"depth", "+3"}}).values()[1].number == 3);
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"depth", "+-3"}}), Catch::Contains("not a number"));
}

TEST_CASE("a setting without '=' is named, with the colour hint only where it fits", "[params]") {
    using Catch::Contains;
    CHECK_THROWS_WITH(hsr::parse_plugin_spec("octree-zbuffer:max-depth"),
                      Contains("'max-depth' in 'octree-zbuffer:max-depth' is not key=value") && !Contains("colour"));
    CHECK_THROWS_WITH(hsr::parse_plugin_spec("phong:tint=1,0.5,0"), Contains("(a colour is written r/g/b)"));
}

TEST_CASE("bad settings are errors that name the plugin and the key", "[params]") {
    const hsr_plugin_descriptor d = make_descriptor();
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"colour", "1/1/1"}}),
                      Catch::Contains("plugin 'demo' has no parameter 'colour'") && Catch::Contains("tint"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"depth", "9"}}), Catch::Contains("out of range [1, 8]"));
    // The value as the user wrote it, not as a double prints it (1e+11).
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"depth", "99999999999"}}),
                      Catch::Contains("99999999999 is out of range"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"depth", "2.5"}}), Catch::Contains("not a whole number"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"shininess", "shiny"}}), Catch::Contains("not a number"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"shininess", "nan"}}), Catch::Contains("not a number"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"test", "equal"}}), Catch::Contains("not one of less|greater"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"cull", "maybe"}}), Catch::Contains("not a boolean"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"tint", "1/2/0"}}), Catch::Contains("not a colour"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"depth", "2"}, {"depth", "3"}}), Catch::Contains("given twice"));
}

TEST_CASE("integer parameters show their ranges as whole numbers at any size", "[params]") {
    const hsr_param_desc big{sizeof(hsr_param_desc), "max-polygons", HSR_PARAM_INT, "1000000", 1, 1e8, nullptr, "m"};
    const hsr_param_desc huge{sizeof(hsr_param_desc), "max-candidates", HSR_PARAM_INT, "1", 1, 1e15, nullptr, "c"};
    const hsr_param_desc scale{sizeof(hsr_param_desc), "scale", HSR_PARAM_FLOAT, "1", 0, 1e8, nullptr, "s"};
    CHECK_THAT(hsr::describe_param(big), Catch::Contains("(integer 1..100000000)"));
    CHECK_THAT(hsr::describe_param(huge), Catch::Contains("(integer 1..1000000000000000)"));
    CHECK_THAT(hsr::describe_param(scale), Catch::Contains("(0..1e+08)"));
    CHECK_THROWS_WITH(hsr::parse_param_value(big, "200000000"), Catch::Contains("out of range [1, 100000000]"));
}

TEST_CASE("a mistyped parameter name is answered with the nearest one", "[params]") {
    const hsr_plugin_descriptor d = make_descriptor();
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"dpeth", "2"}}),
                      Catch::Contains("plugin 'demo' has no parameter 'dpeth' (did you mean depth?)"));
    CHECK_THROWS_WITH(hsr::resolve_params(d, {{"colour", "1/1/1"}}), !Catch::Contains("did you mean"));
}
