// phong: the Phong reflection model with Phong shading by default.
//   colour = ka*C + sum_l E_l * (kd*C*max(0, N.L) + ks*S*max(0, R.V)^n),  R = 2(N.L)N - L
// B. T. Phong, "Illumination for computer generated pictures", CACM 18(6), 1975: the specular term
// from the mirror direction R, and interpolating the normal across a face so highlights inside a
// triangle are not lost. interpolation=gouraud evaluates the model at the corners only
// (H. Gouraud, "Continuous shading of curved surfaces", 1971). Formulas: hsr/shading.hpp.
#include "hsr/sdk.hpp"
#include "hsr/shading.hpp"

namespace {

class Phong final : public hsr::shading::ShadedLightingModel<hsr::shading::PhongSpecular> {
public:
    static constexpr hsr::sdk::PluginInfo info{"phong", "1.0.0",
                                               "Phong reflection (R.V highlight), per-pixel normals by default"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::shading::param::interpolation("phong"),
        hsr::shading::param::ambient(),
        hsr::shading::param::diffuse(),
        hsr::shading::param::specular(),
        hsr::shading::param::shininess("32"),
        hsr::shading::param::specular_color(),
        hsr::shading::param::two_sided(),
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "модель освещения Фонга (блик по R·V); по умолчанию затенение по Фонгу (нормаль в каждом пикселе)"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, hsr::shading::param::diffuse_translations, hsr::shading::param::specular_translations);

    explicit Phong(const hsr::sdk::Params& p)
        : ShadedLightingModel(hsr::shading::read_material(p, /*with_specular=*/true)) {}
};

}  // namespace

HSR_EXPORT_PLUGIN(Phong)
