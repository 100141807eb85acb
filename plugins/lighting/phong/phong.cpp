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

    static inline const hsr::sdk::TranslationSpec translations[] = {
        {"ru", "description",
         "модель освещения Фонга (блик по R·V); по умолчанию затенение по Фонгу (нормаль в каждом пикселе)"},
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
        {"ru", "param:specular", "коэффициент зеркального отражения"},
        {"ru", "help:specular", "коэффициент ks зеркального отражения"},
        {"ru", "param:shininess", "показатель блеска"},
        {"ru", "help:shininess",
         "показатель степени n зеркальной составляющей: чем он больше, тем блик меньше и резче"},
        {"ru", "param:specular-color", "цвет блика"},
        {"ru", "help:specular-color", "цвет зеркального блика"},
        {"ru", "param:two-sided", "двустороннее освещение"},
        {"ru", "help:two-sided",
         "освещать обратную сторону грани так же, как лицевую (для незамкнутых сеток и взгляда изнутри)"},
    };

    explicit Phong(const hsr::sdk::Params& p)
        : ShadedLightingModel(hsr::shading::read_material(p, /*with_specular=*/true)) {}
};

}  // namespace

HSR_EXPORT_PLUGIN(Phong)
