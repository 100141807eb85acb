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

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "модель Ламберта: диффузное отражение и фоновое освещение; по умолчанию плоское затенение"},
        {"ru", "param:interpolation", "затенение"},
        {"ru", "help:interpolation",
         "плоское — один цвет на грань; по Гуро — цвета, найденные в вершинах, интерполируются вдоль грани; по "
         "Фонгу — интерполируется нормаль, и модель вычисляется в каждом пикселе"},
        {"ru", "choice:interpolation:flat", "плоское"},
        {"ru", "choice:interpolation:gouraud", "по Гуро"},
        {"ru", "choice:interpolation:phong", "по Фонгу"},
        {"ru", "param:ambient", "коэффициент фонового освещения"},
        {"ru", "help:ambient", "коэффициент ka рассеянного фонового света (умножается на цвет грани)"},
        {"ru", "param:diffuse", "коэффициент диффузного отражения"},
        {"ru", "help:diffuse", "коэффициент kd диффузного отражения (умножается на цвет грани)"},
        {"ru", "param:two-sided", "двустороннее освещение"},
        {"ru", "help:two-sided",
         "освещать обратную сторону грани так же, как лицевую (для незамкнутых сеток и взгляда изнутри)"},
    };

    explicit Lambert(const hsr::sdk::Params& p)
        : ShadedLightingModel(hsr::shading::read_material(p, /*with_specular=*/false)) {}
};

}  // namespace

HSR_EXPORT_PLUGIN(Lambert)
