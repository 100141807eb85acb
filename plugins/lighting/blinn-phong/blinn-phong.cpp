// blinn-phong: Phong's model with Blinn's half-vector highlight, per-pixel normals by default.
//   colour = ka*C + sum_l E_l * (kd*C*max(0, N.L) + ks*S*max(0, N.H)^n),  H = normalize(L + V)
// J. F. Blinn, "Models of light reflection for computer synthesized pictures", SIGGRAPH 1977: N.H
// replaces Phong's R.V (B. T. Phong, CACM 1975). The angle between N and H is about half that between
// R and V, so N.H falls off more slowly and needs a larger exponent for a comparable highlight (default
// 64 against Phong's 32). interpolation=gouraud|flat as in Gouraud (1971). Formulas: hsr/shading.hpp.
#include "hsr/sdk.hpp"
#include "hsr/shading.hpp"

namespace {

class BlinnPhong final : public hsr::shading::ShadedLightingModel<hsr::shading::BlinnPhongSpecular> {
public:
    static constexpr hsr::sdk::PluginInfo info{"blinn-phong", "1.0.0",
                                               "Blinn-Phong reflection (N.H highlight), per-pixel normals by default"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::shading::param::interpolation("phong"),
        hsr::shading::param::ambient(),
        hsr::shading::param::diffuse(),
        hsr::shading::param::specular(),
        hsr::shading::param::shininess("64"),
        hsr::shading::param::specular_color(),
        hsr::shading::param::two_sided(),
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "модель освещения Блинна — Фонга (блик по N·H); по умолчанию затенение по Фонгу (нормаль в каждом "
         "пикселе)"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, hsr::shading::param::diffuse_translations, hsr::shading::param::specular_translations);

    explicit BlinnPhong(const hsr::sdk::Params& p)
        : ShadedLightingModel(hsr::shading::read_material(p, /*with_specular=*/true)) {}
};

}  // namespace

HSR_EXPORT_PLUGIN(BlinnPhong)
