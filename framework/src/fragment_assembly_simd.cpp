// SIMD parts of a shading band (fragment_assembly.hpp), on Google Highway with the best instruction
// set of the CPU chosen at run time: finding the covered pixels (a vector of face ids compared at
// once), assembling their fragments (the float operations of assemble_fragment, in its order, on as
// many fragments as a vector has lanes; in an instanced scene carried into world space by the
// fragment's instance) and turning colours into bytes, written straight into the picture a run of
// pixels at a time. Bit-identical to the scalar code.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fragment_assembly_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include "fragment_assembly.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace hsr::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

uint32_t FindCoveredPixels(const uint32_t* face, const uint32_t* instance, uint32_t pixel_begin, uint32_t pixel_end,
                           FragmentArrays& out) {
    using namespace hn;
    const ScalableTag<uint32_t> du;
    const uint32_t lanes = uint32_t(Lanes(du));
    const auto no_face = Set(du, HSR_NO_FACE);

    // A vector's worth of faces tested at once: stored whole when all are covered (inside an
    // object), else the covered ones taken bit by bit.
    uint32_t n = 0;
    uint32_t p = pixel_begin;
    HWY_ALIGN uint8_t covered_bits[8];
    for (; p + lanes <= pixel_end; p += lanes) {
        const auto faces = LoadU(du, face + p);
        const auto covered = Ne(faces, no_face);
        if (AllFalse(du, covered)) continue;
        if (AllTrue(du, covered)) {
            StoreU(faces, du, out.face.data() + n);
            StoreU(Iota(du, p), du, out.pixel.data() + n);
            n += lanes;
            continue;
        }
        StoreMaskBits(du, covered, covered_bits);
        for (uint32_t byte = 0; byte < (lanes + 7) / 8; ++byte)
            for (uint32_t bits = covered_bits[byte]; bits != 0; bits &= bits - 1) {
                const uint32_t q = p + 8 * byte + uint32_t(std::countr_zero(bits));
                out.face[n] = face[q];
                out.pixel[n++] = q;
            }
    }
    for (; p < pixel_end; ++p)
        if (face[p] != HSR_NO_FACE) out.face[n] = face[p], out.pixel[n++] = p;
    if (instance != nullptr)
        for (uint32_t i = 0; i < n; ++i) out.instance[i] = instance[out.pixel[i]];
    return n;
}

void AssembleCoveredFragments(const hsr_scene& scene, const Placements& placements, bool instanced, const float* bary,
                              uint32_t first, uint32_t count, uint32_t total, FragmentArrays& out) {
    using namespace hn;
    const ScalableTag<uint32_t> du;
    const RebindToSigned<decltype(du)> di;
    const RebindToFloat<decltype(du)> df;
    const uint32_t lanes = uint32_t(Lanes(du));
    // Covered pixel f = first + i becomes fragment i.
    const uint32_t* face = out.face.data() + first;
    const uint32_t* pixel_of = out.pixel.data() + first;
    const uint32_t* instance_of = out.instance.data() + first;
    const uint32_t ahead_end = total - first;  // the band's covered pixels that may be asked for ahead
    const uint32_t n = count;

    // Their fragments, a block at a time: a scalar pass copies each fragment's corners (normals,
    // then positions) and barycentrics into columns, from which the arithmetic runs a vector at a
    // time. (Loads lane by lane beat gather instructions, which are slow on some CPUs.) The last
    // few fragments are done as assemble_fragment does them.
    constexpr uint32_t kBlock = 64;
    constexpr uint32_t kPrefetchDistance = 16;
    HWY_ALIGN float column[20][kBlock];  // 0-8: corner normals, 9-17: corner positions, 18-19: b1, b2
    // An instanced scene's placements, lane by lane, for a vector whose fragments are of several
    // instances: the transform's rows 0-2 by column (m[c][r] at 3 c + r), then the rotation (r[c][r]
    // at 12 + 3 c + r).
    HWY_ALIGN float placement[21][HWY_MAX_BYTES / sizeof(float)];
    const auto one = Set(df, 1.0f);
    const auto zero = Zero(df);
    uint32_t i = 0;
    const uint32_t vector_end = n - n % lanes;
    while (i < vector_end) {
        const uint32_t block = std::min(kBlock, vector_end - i);
        for (uint32_t j = 0; j < block; ++j) {
            // The corner data comes in screen order, not memory order: ask for it ahead, the
            // triangle's corner indices twice as far ahead as the positions they lead to, and the
            // face normal and colour, which the lighting kernel reads next.
            if (i + j + 2 * kPrefetchDistance < ahead_end) {
                const uint32_t far_ahead = face[i + j + 2 * kPrefetchDistance];
                hwy::Prefetch(scene.indices + 3 * size_t{far_ahead});
                hwy::Prefetch(scene.corner_normals + 9 * size_t{far_ahead});
                hwy::Prefetch(scene.corner_normals + 9 * size_t{far_ahead} + 8);
                hwy::Prefetch(scene.face_normals + 3 * size_t{far_ahead});
                if (scene.face_colors != nullptr) hwy::Prefetch(scene.face_colors + 3 * size_t{far_ahead});
            }
            if (i + j + kPrefetchDistance < ahead_end) {
                const uint32_t* ahead_tri = scene.indices + 3 * size_t{face[i + j + kPrefetchDistance]};
                for (int c = 0; c < 3; ++c) hwy::Prefetch(scene.positions + 3 * size_t{ahead_tri[c]});
            }
            const uint32_t t = face[i + j];
            const uint32_t pixel = pixel_of[i + j];
            const float* corner_normal = scene.corner_normals + 9 * size_t{t};
            for (int k = 0; k < 9; ++k) column[k][j] = corner_normal[k];
            const uint32_t* tri = scene.indices + 3 * size_t{t};
            for (int c = 0; c < 3; ++c) {
                const float* p = scene.positions + 3 * size_t{tri[c]};
                for (int k = 0; k < 3; ++k) column[9 + 3 * c + k][j] = p[k];
            }
            column[18][j] = bary[2 * size_t{pixel}];
            column[19][j] = bary[2 * size_t{pixel} + 1];
        }
        for (uint32_t j = 0; j < block; j += lanes, i += lanes) {
            const auto b1 = Load(df, column[18] + j);
            const auto b2 = Load(df, column[19] + j);
            const auto b0 = Sub(Sub(one, b1), b2);
            Vec<decltype(df)> normal[3], position[3];
            for (int k = 0; k < 3; ++k) {
                normal[k] = Add(Add(Mul(b0, Load(df, column[k] + j)), Mul(b1, Load(df, column[3 + k] + j))),
                                Mul(b2, Load(df, column[6 + k] + j)));
                position[k] = Add(Add(Mul(b0, Load(df, column[9 + k] + j)), Mul(b1, Load(df, column[12 + k] + j))),
                                  Mul(b2, Load(df, column[15 + k] + j)));
            }
            const auto length =
                Sqrt(Add(Add(Mul(normal[0], normal[0]), Mul(normal[1], normal[1])), Mul(normal[2], normal[2])));
            const auto has_length = Gt(length, zero);
            for (int k = 0; k < 3; ++k) normal[k] = Div(normal[k], length);
            if (!AllTrue(df, has_length)) {  // no interpolated normal: the face normal
                const auto t3 = Mul(BitCast(di, LoadU(du, face + i)), Set(di, 3));
                for (int k = 0; k < 3; ++k)
                    normal[k] = IfThenElse(has_length, normal[k], GatherIndex(df, scene.face_normals, Add(t3, Set(di, k))));
            }
            if (instanced) {  // glm's mat4 * vec4(p, 1) and mat3 * n, in their order
                // Mostly every lane is of one instance, whose placement is then broadcast.
                const uint32_t lane_0 = instance_of[i];
                const bool one_instance = AllTrue(du, Eq(LoadU(du, instance_of + i), Set(du, lane_0)));
                if (!one_instance)
                    for (uint32_t lane = 0; lane < lanes; ++lane) {
                        const glm::mat4& m = placements.transform[instance_of[i + lane]];
                        const glm::mat3& r = placements.rotation[instance_of[i + lane]];
                        for (int c = 0; c < 4; ++c)
                            for (int row = 0; row < 3; ++row) placement[3 * c + row][lane] = m[c][row];
                        for (int c = 0; c < 3; ++c)
                            for (int row = 0; row < 3; ++row) placement[12 + 3 * c + row][lane] = r[c][row];
                    }
                const glm::mat4& m_first = placements.transform[lane_0];
                const glm::mat3& r_first = placements.rotation[lane_0];
                const auto m = [&](int c, int row) {
                    return one_instance ? Set(df, m_first[c][row]) : Load(df, placement[3 * c + row]);
                };
                const auto r = [&](int c, int row) {
                    return one_instance ? Set(df, r_first[c][row]) : Load(df, placement[12 + 3 * c + row]);
                };
                Vec<decltype(df)> world[3], turned[3];
                for (int row = 0; row < 3; ++row) {
                    // (m[3] * 1 is m[3])
                    world[row] = Add(Add(Mul(m(0, row), position[0]), Mul(m(1, row), position[1])),
                                     Add(Mul(m(2, row), position[2]), m(3, row)));
                    turned[row] = Add(Add(Mul(r(0, row), normal[0]), Mul(r(1, row), normal[1])), Mul(r(2, row), normal[2]));
                }
                for (int k = 0; k < 3; ++k) position[k] = world[k], normal[k] = turned[k];
            }
            StoreInterleaved2(b1, b2, df, out.bary.data() + 2 * size_t{i});
            StoreInterleaved3(position[0], position[1], position[2], df, out.position.data() + 3 * size_t{i});
            StoreInterleaved3(normal[0], normal[1], normal[2], df, out.normal.data() + 3 * size_t{i});
        }
    }
    for (; i < n; ++i) {
        const uint32_t pixel = pixel_of[i];
        const float b1 = bary[2 * size_t{pixel}], b2 = bary[2 * size_t{pixel} + 1];
        glm::vec3 position, normal;
        fragment_geometry(scene, placements, face[i], instanced ? instance_of[i] : kNotInstanced, b1, b2, position,
                          normal);
        out.bary[2 * size_t{i}] = b1;
        out.bary[2 * size_t{i} + 1] = b2;
        for (int k = 0; k < 3; ++k) {
            out.position[3 * size_t{i} + k] = position[k];
            out.normal[3 * size_t{i} + k] = normal[k];
        }
    }
}

HWY_INLINE void BytesOfColors(const float* color, size_t count, uint8_t* bytes) {
    using namespace hn;
    const ScalableTag<float> df;
    const RebindToSigned<decltype(df)> di;
    const Rebind<uint8_t, decltype(df)> d8;
    const size_t lanes = Lanes(df);
    size_t i = 0;
    for (; i + lanes <= count; i += lanes) {
        // Held to [0, 1] first (NaN to 0), so that the conversion never sees a value out of range:
        // 1 becomes 255.5, which truncates to 255, and 0 becomes 0.5, which truncates to 0.
        const auto v = LoadU(df, color + i);
        const auto held = Min(IfThenElseZero(Gt(v, Zero(df)), v), Set(df, 1.0f));
        const auto b = ConvertTo(di, Add(Mul(held, Set(df, 255.0f)), Set(df, 0.5f)));
        StoreU(DemoteTo(d8, b), d8, bytes + i);
    }
    for (; i < count; ++i) bytes[i] = color_to_byte(color[i]);
}

void ColorsToBytes(const float* color, size_t count, uint8_t* bytes) { BytesOfColors(color, count, bytes); }

void ColorsToPixels(const float* color, const uint32_t* pixel, uint32_t count, uint8_t* rgb) {
    // Covered pixels come in runs along a row, and a run's colours are consecutive bytes of the
    // picture: a vector's lane count of fragments whose pixels are consecutive (the pixels rise, so
    // the first and last tell) is converted three vectors at a time, other fragments one by one.
    const uint32_t lanes = uint32_t(hn::Lanes(hn::ScalableTag<float>()));
    uint32_t i = 0;
    while (i < count) {
        if (i + lanes <= count && pixel[i + lanes - 1] - pixel[i] == lanes - 1) {
            BytesOfColors(color + 3 * size_t{i}, 3 * size_t{lanes}, rgb + 3 * size_t{pixel[i]});
            i += lanes;
        } else {
            for (int k = 0; k < 3; ++k) rgb[3 * size_t{pixel[i]} + k] = color_to_byte(color[3 * size_t{i} + k]);
            ++i;
        }
    }
}

}  // namespace hsr::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hsr {

HWY_EXPORT(FindCoveredPixels);
HWY_EXPORT(AssembleCoveredFragments);
HWY_EXPORT(ColorsToBytes);
HWY_EXPORT(ColorsToPixels);

uint32_t find_covered_pixels(const uint32_t* face, const uint32_t* instance, uint32_t pixel_begin, uint32_t pixel_end,
                             FragmentArrays& out) {
    return HWY_DYNAMIC_DISPATCH(FindCoveredPixels)(face, instance, pixel_begin, pixel_end, out);
}

void assemble_covered_fragments(const hsr_scene& scene, const Placements& placements, bool instanced, const float* bary,
                                uint32_t first, uint32_t count, uint32_t total, FragmentArrays& out) {
    HWY_DYNAMIC_DISPATCH(AssembleCoveredFragments)(scene, placements, instanced, bary, first, count, total, out);
}

void colors_to_bytes(const float* color, size_t count, uint8_t* bytes) {
    HWY_DYNAMIC_DISPATCH(ColorsToBytes)(color, count, bytes);
}

void colors_to_pixels(const float* color, const uint32_t* pixel, uint32_t count, uint8_t* rgb) {
    HWY_DYNAMIC_DISPATCH(ColorsToPixels)(color, pixel, count, rgb);
}

}  // namespace hsr
#endif
