// lambert: ambient + Lambertian diffuse reflection, by default flat shaded (one colour per face).
//   colour = ka*C + sum_l E_l * kd*C*max(0, N.L)
// Lambert's cosine law (J. H. Lambert, Photometria, 1760), as used for flat shading in the early
// hidden-surface literature; with interpolation=gouraud it is Gouraud's "Continuous shading of curved
// surfaces" (IEEE Trans. Computers, 1971), with interpolation=phong the normal is interpolated
// (Phong 1975). The formulas and interpolation machinery live in hsr/shading.hpp.
#include "hsr/sdk.hpp"
#include "hsr/shading.hpp"

namespace {

class Lambert final : public hsr::shading::ShadedLightingModel<hsr::shading::NoSpecular> {
public:
    static constexpr hsr::sdk::PluginInfo info{"lambert", "1.0.0",
                                               "Lambert diffuse + ambient lighting, flat shaded by default"};
    static inline const hsr::sdk::ParamSpec params[] = {
        hsr::shading::param::interpolation("flat"),
        hsr::shading::param::ambient(),
        hsr::shading::param::diffuse(),
        hsr::shading::param::two_sided(),
    };

    static constexpr hsr::sdk::TranslationSpec own_translations[] = {
        {"ru", "description",
         "модель Ламберта: диффузное отражение и фоновое освещение; по умолчанию плоское затенение"},
    };
    static constexpr auto translations = hsr::sdk::join_translations(
        own_translations, hsr::shading::param::diffuse_translations);

    explicit Lambert(const hsr::sdk::Params& p)
        : ShadedLightingModel(hsr::shading::read_material(p, /*with_specular=*/false)) {}
};

}  // namespace

HSR_EXPORT_PLUGIN(Lambert)
