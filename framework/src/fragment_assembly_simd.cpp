// SIMD parts of a shading band (fragment_assembly.hpp) for scenes without instances, on Google
// Highway with the best instruction set of the CPU chosen at run time: finding the covered pixels
// (compress-store), assembling their fragments (the float operations of assemble_fragment, in its
// order, on as many fragments as a vector has lanes) and turning colours into bytes. Bit-identical
// to the scalar code.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fragment_assembly_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "fragment_assembly.hpp"

#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace hsr::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

uint32_t AssembleCoveredPixels(const hsr_scene& scene, const uint32_t* face, const float* bary, uint32_t pixel_begin,
                               uint32_t pixel_end, FragmentArrays& out) {
    using namespace hn;
    const ScalableTag<uint32_t> du;
    const RebindToSigned<decltype(du)> di;
    const RebindToFloat<decltype(du)> df;
    const uint32_t lanes = uint32_t(Lanes(du));
    const auto no_face = Set(du, HSR_NO_FACE);

    // The covered pixels, in pixel order (the arrays have room for a whole vector past the end).
    uint32_t n = 0;
    uint32_t p = pixel_begin;
    for (; p + lanes <= pixel_end; p += lanes) {
        const auto faces = LoadU(du, face + p);
        const auto covered = Ne(faces, no_face);
        if (AllFalse(du, covered)) continue;
        CompressStore(Iota(du, p), covered, du, out.pixel.data() + n);
        n += uint32_t(CompressStore(faces, covered, du, out.face.data() + n));
    }
    for (; p < pixel_end; ++p)
        if (face[p] != HSR_NO_FACE) out.face[n] = face[p], out.pixel[n++] = p;

    // Their fragments, a vector at a time; the last few as assemble_fragment does them.
    const auto* indices = reinterpret_cast<const int32_t*>(scene.indices);
    const auto one = Set(df, 1.0f);
    const auto zero = Zero(df);
    uint32_t i = 0;
    for (; i + lanes <= n; i += lanes) {
        const auto t = BitCast(di, LoadU(du, out.face.data() + i));
        const auto pixel2 = ShiftLeft<1>(BitCast(di, LoadU(du, out.pixel.data() + i)));
        const auto b1 = GatherIndex(df, bary, pixel2);
        const auto b2 = GatherIndex(df, bary, Add(pixel2, Set(di, 1)));
        const auto b0 = Sub(Sub(one, b1), b2);
        const auto t3 = Mul(t, Set(di, 3));
        const auto t9 = Mul(t, Set(di, 9));
        const Vec<decltype(di)> vertex3[3] = {Mul(GatherIndex(di, indices, t3), Set(di, 3)),
                                              Mul(GatherIndex(di, indices, Add(t3, Set(di, 1))), Set(di, 3)),
                                              Mul(GatherIndex(di, indices, Add(t3, Set(di, 2))), Set(di, 3))};
        Vec<decltype(df)> normal[3], position[3];
        for (int k = 0; k < 3; ++k) {
            const auto c = Set(di, k);
            normal[k] = Add(Add(Mul(b0, GatherIndex(df, scene.corner_normals, Add(t9, c))),
                                Mul(b1, GatherIndex(df, scene.corner_normals, Add(t9, Set(di, 3 + k))))),
                            Mul(b2, GatherIndex(df, scene.corner_normals, Add(t9, Set(di, 6 + k)))));
            position[k] = Add(Add(Mul(b0, GatherIndex(df, scene.positions, Add(vertex3[0], c))),
                                  Mul(b1, GatherIndex(df, scene.positions, Add(vertex3[1], c)))),
                              Mul(b2, GatherIndex(df, scene.positions, Add(vertex3[2], c))));
        }
        const auto length = Sqrt(Add(Add(Mul(normal[0], normal[0]), Mul(normal[1], normal[1])), Mul(normal[2], normal[2])));
        const auto has_length = Gt(length, zero);
        for (int k = 0; k < 3; ++k) normal[k] = Div(normal[k], length);
        if (!AllTrue(df, has_length)) {  // no interpolated normal: the face normal
            for (int k = 0; k < 3; ++k)
                normal[k] = IfThenElse(has_length, normal[k], GatherIndex(df, scene.face_normals, Add(t3, Set(di, k))));
        }
        StoreInterleaved2(b1, b2, df, out.bary.data() + 2 * size_t{i});
        StoreInterleaved3(position[0], position[1], position[2], df, out.position.data() + 3 * size_t{i});
        StoreInterleaved3(normal[0], normal[1], normal[2], df, out.normal.data() + 3 * size_t{i});
    }
    const Placements no_placements{};
    for (; i < n; ++i) {
        const uint32_t pixel = out.pixel[i];
        assemble_fragment(scene, no_placements, out.face[i], kNotInstanced, bary[2 * size_t{pixel}],
                          bary[2 * size_t{pixel} + 1], pixel, out, i);
    }
    return n;
}

void ColorsToBytes(const float* color, size_t count, uint8_t* bytes) {
    using namespace hn;
    const ScalableTag<float> df;
    const RebindToSigned<decltype(df)> di;
    const Rebind<uint8_t, decltype(df)> d8;
    const size_t lanes = Lanes(df);
    size_t i = 0;
    for (; i + lanes <= count; i += lanes) {
        const auto v = LoadU(df, color + i);
        auto b = ConvertTo(di, Add(Mul(v, Set(df, 255.0f)), Set(df, 0.5f)));
        b = IfThenElse(RebindMask(di, Ge(v, Set(df, 1.0f))), Set(di, 255), b);
        b = IfThenZeroElse(RebindMask(di, Not(Gt(v, Zero(df)))), b);
        StoreU(DemoteTo(d8, b), d8, bytes + i);
    }
    for (; i < count; ++i) bytes[i] = color_to_byte(color[i]);
}

}  // namespace hsr::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hsr {

HWY_EXPORT(AssembleCoveredPixels);
HWY_EXPORT(ColorsToBytes);

uint32_t assemble_covered_pixels(const hsr_scene& scene, const uint32_t* face, const float* bary, uint32_t pixel_begin,
                                 uint32_t pixel_end, FragmentArrays& out) {
    return HWY_DYNAMIC_DISPATCH(AssembleCoveredPixels)(scene, face, bary, pixel_begin, pixel_end, out);
}

void colors_to_bytes(const float* color, size_t count, uint8_t* bytes) {
    HWY_DYNAMIC_DISPATCH(ColorsToBytes)(color, count, bytes);
}

}  // namespace hsr
#endif
