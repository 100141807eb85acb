// bsp: building the tree (Fuchs, Kedem & Naylor 1980, section 3) in world space, without
// recursion (a tree of a closed mesh can be thousands of nodes deep). See bsp_tree.hpp.
#include "bsp_tree.hpp"

#include "hsr/triangle_setup.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace bsp {

namespace {

bool is_finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

[[noreturn]] void refuse(const BuildParams& params, const BuildStats& stats) {
    const std::string why = stats.polygons_split == 0
                                ? std::to_string(stats.polygons_in) + " triangles before any split"
                                : std::to_string(stats.polygons_in) + " triangles, " +
                                      std::to_string(stats.polygons_split) + " split so far";
    throw hsr::sdk::Unsupported("bsp: more than max-polygons=" + std::to_string(params.max_polygons) +
                                " polygons after splits (" + why + "); raise max-polygons");
}

}  // namespace

void Tree::clear() {
    nodes.clear();
    triangles.clear();
    polygons.clear();
    corners.clear();
    cuts.clear();
    stats = BuildStats{};
    epsilon = 0.0;
}

Tree::Side Tree::classify(const Polygon& polygon, const glm::dvec4& plane) const {
    bool front = false, back = false;
    const glm::dvec3 normal(plane);
    for (uint32_t k = 0; k < polygon.corner_count; ++k) {
        const double d = glm::dot(normal, corners[polygon.first_corner + k]) + plane.w;
        front |= d > epsilon;
        back |= d < -epsilon;
    }
    return front ? (back ? Side::kSpanning : Side::kFront) : (back ? Side::kBack : Side::kOn);
}

// The paper leaves the choice open and suggests trying a few candidates for the fewest splits;
// ties go to the candidate that divides the rest more evenly, which keeps the tree shallower.
// Candidates are scored against 1/k of the list (at least kScoredPolygons of it), spread evenly
// over it, so that choosing costs about as much as partitioning the list: a tree of a closed mesh
// is deep, most nodes hold long lists, and scoring every candidate against all of the list costs
// k times the whole build (3 s instead of 1 s on the bunny).
constexpr size_t kScoredPolygons = 32;

uint32_t Tree::choose_splitter(const std::vector<uint32_t>& list, const BuildParams& params) const {
    if (params.choice == SplitChoice::kFirst || list.size() == 1) return 0;
    const size_t samples = std::min<size_t>(params.samples, list.size());
    const size_t scored = std::min(list.size(), std::max(kScoredPolygons, list.size() / samples));
    uint32_t best = 0;
    uint64_t best_splits = UINT64_MAX, best_imbalance = UINT64_MAX;
    for (size_t s = 0; s < samples; ++s) {
        const uint32_t candidate = uint32_t(s * list.size() / samples);  // evenly spread over the list
        const glm::dvec4 plane = triangles[polygons[list[candidate]].triangle].plane;
        Split split;
        for (size_t k = 0; k < scored; ++k) {
            const size_t at = k * list.size() / scored;
            if (at == candidate) continue;
            switch (classify(polygons[list[at]], plane)) {
                case Side::kOn: break;
                case Side::kFront: ++split.front; break;
                case Side::kBack: ++split.back; break;
                case Side::kSpanning: ++split.spanning; break;
            }
            if (split.spanning > best_splits) break;
        }
        const uint64_t imbalance = split.front > split.back ? split.front - split.back : split.back - split.front;
        if (split.spanning < best_splits || (split.spanning == best_splits && imbalance < best_imbalance)) {
            best = candidate;
            best_splits = split.spanning;
            best_imbalance = imbalance;
        }
    }
    return best;
}

// A convex piece of `from`, cut off by `cut`, becomes a polygon of its own. A piece with more
// corners than the rasterizer takes (a cut adds one) is halved along a diagonal; the halves share
// the piece's cuts and their pixel centres are told apart by one more cut, along that diagonal.
void Tree::add_piece(const glm::dvec3* piece, int count, const Polygon& from, const Cut* cut,
                     std::vector<uint32_t>& list, const BuildParams& params) {
    if (count < 3) return;
    if (count > hsr::raster::kMaxPieceVertices) {
        const int half = count / 2;
        glm::dvec3 rest[hsr::raster::kMaxPieceVertices + 2];
        std::copy(piece + half, piece + count, rest);
        rest[count - half] = piece[0];
        // The plane through the diagonal (piece[0], piece[half]) and the triangle's normal.
        const Triangle& t = triangles[from.triangle];
        const glm::dvec3 normal = glm::cross(glm::dvec3(t.plane), piece[half] - piece[0]);
        const glm::dvec4 plane(normal, -glm::dot(normal, piece[0]));
        const bool first_in_front = glm::dot(normal, piece[1]) + plane.w > 0.0;
        // The first half goes in as a piece with the diagonal's cut; then the rest with the other.
        Polygon with_cut = from;
        if (cut != nullptr) {
            with_cut.first_cut = uint32_t(cuts.size());
            cuts.insert(cuts.end(), cuts.begin() + from.first_cut, cuts.begin() + from.first_cut + from.cut_count);
            cuts.push_back(*cut);
            with_cut.cut_count = from.cut_count + 1;
        }
        const Cut first_cut = cut_of(from.triangle, plane, first_in_front);
        const Cut rest_cut = cut_of(from.triangle, plane, !first_in_front);
        add_piece(piece, half + 1, with_cut, &first_cut, list, params);
        add_piece(rest, count - half + 1, with_cut, &rest_cut, list, params);
        return;
    }
    if (++stats.polygons_after_splits > params.max_polygons) refuse(params, stats);
    Polygon p = from;
    p.first_corner = uint32_t(corners.size());
    p.corner_count = uint32_t(count);
    corners.insert(corners.end(), piece, piece + count);
    if (cut != nullptr) {
        p.first_cut = uint32_t(cuts.size());
        cuts.insert(cuts.end(), cuts.begin() + from.first_cut, cuts.begin() + from.first_cut + from.cut_count);
        cuts.push_back(*cut);
        p.cut_count = from.cut_count + 1;
    }
    list.push_back(uint32_t(polygons.size()));
    polygons.push_back(p);
}

Cut Tree::cut_of(uint32_t triangle, const glm::dvec4& plane, bool front) const {
    const Triangle& t = triangles[triangle];
    const glm::dvec3 normal(plane);
    return {{glm::dot(normal, t.corner[0]) + plane.w, glm::dot(normal, t.corner[1] - t.corner[0]),
             glm::dot(normal, t.corner[2] - t.corner[0])},
            front};
}

// Cuts polygon `index` by the plane. Corners within epsilon of the plane go to both pieces; a
// crossing corner is computed once, from the front end toward the back end, and shared.
void Tree::split(uint32_t index, const glm::dvec4& plane, std::vector<uint32_t>& front, std::vector<uint32_t>& back,
                 const BuildParams& params) {
    const Polygon from = polygons[index];
    glm::dvec3 in[hsr::raster::kMaxPieceVertices];
    double distance[hsr::raster::kMaxPieceVertices];
    const glm::dvec3 normal(plane);
    const int count = int(from.corner_count);
    for (int k = 0; k < count; ++k) {
        in[k] = corners[from.first_corner + k];
        const double d = glm::dot(normal, in[k]) + plane.w;
        distance[k] = d > epsilon ? d : d < -epsilon ? d : 0.0;
    }
    glm::dvec3 front_piece[hsr::raster::kMaxPieceVertices + 1], back_piece[hsr::raster::kMaxPieceVertices + 1];
    int front_count = 0, back_count = 0;
    for (int k = 0; k < count; ++k) {
        const int next = k + 1 == count ? 0 : k + 1;
        const double da = distance[k], db = distance[next];
        if (da >= 0.0) front_piece[front_count++] = in[k];
        if (da <= 0.0) back_piece[back_count++] = in[k];
        if ((da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0)) {
            const glm::dvec3& f = da > 0.0 ? in[k] : in[next];
            const glm::dvec3& b = da > 0.0 ? in[next] : in[k];
            const double d_front = std::max(da, db), d_back = std::min(da, db);
            const glm::dvec3 crossing = f + (d_front / (d_front - d_back)) * (b - f);
            front_piece[front_count++] = crossing;
            back_piece[back_count++] = crossing;
        }
    }
    ++stats.polygons_split;
    --stats.polygons_after_splits;  // the polygon cut, replaced by its pieces
    const Cut front_cut = cut_of(from.triangle, plane, true), back_cut = cut_of(from.triangle, plane, false);
    add_piece(front_piece, front_count, from, &front_cut, front, params);
    add_piece(back_piece, back_count, from, &back_cut, back, params);
}

void Tree::build(const hsr::sdk::Scene& scene, const BuildParams& params) {
    clear();
    const uint32_t placements = scene.placement_count();
    uint64_t placed_triangles = 0;
    for (uint32_t k = 0; k < placements; ++k) placed_triangles += scene.placement(k).triangle_count;
    if (placed_triangles > params.max_polygons) {
        stats.polygons_in = placed_triangles;
        refuse(params, stats);
    }
    triangles.reserve(placed_triangles);
    polygons.reserve(placed_triangles);
    corners.reserve(3 * placed_triangles);

    // The placed triangles in world space. Degenerate ones (no plane) cover no pixel centre.
    const uint32_t* indices = scene.raw().indices;
    double largest_coordinate = 0.0;
    std::vector<uint32_t> all;
    all.reserve(placed_triangles);
    for (uint32_t k = 0; k < placements; ++k) {
        const hsr::sdk::Placement p = scene.placement(k);
        const glm::dmat4 world_from_object = p.identity ? glm::dmat4(1.0) : glm::dmat4(p.transform);
        for (uint32_t t = p.first_triangle; t < p.first_triangle + p.triangle_count; ++t) {
            glm::dvec3 w[3];
            for (int c = 0; c < 3; ++c) {
                const glm::dvec3 object(scene.position(indices[3 * size_t(t) + c]));
                w[c] = glm::dvec3(world_from_object * glm::dvec4(object, 1.0));
            }
            if (!(is_finite(w[0]) && is_finite(w[1]) && is_finite(w[2]))) continue;
            const glm::dvec3 cross = glm::cross(w[1] - w[0], w[2] - w[0]);
            const double length = glm::length(cross);
            if (!(length > 0.0) || !std::isfinite(length)) continue;
            const glm::dvec3 normal = cross / length;
            for (const glm::dvec3& c : w)
                largest_coordinate = std::max({largest_coordinate, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
            const uint32_t first = uint32_t(corners.size());
            corners.insert(corners.end(), w, w + 3);
            all.push_back(uint32_t(polygons.size()));
            polygons.push_back({first, 3, uint32_t(triangles.size()), 0, 0});
            triangles.push_back({{w[0], w[1], w[2]}, glm::dvec4(normal, -glm::dot(normal, w[0])), t, p.instance});
        }
    }
    stats.polygons_in = polygons.size();
    stats.polygons_after_splits = polygons.size();
    // A corner's distance to a plane through other double corners is exact to about 1e-16 of the
    // coordinates' size; corners of the float input that are meant to lie in one plane (two
    // triangles of a flat quad, a box face) miss it by that much. 1e-9 of the largest coordinate
    // is far above that rounding and far below anything a pixel can show, so coplanar polygons are
    // kept together and no sliver thinner than rounding is cut off.
    epsilon = 1e-9 * largest_coordinate;
    if (all.empty()) return;

    struct Work {
        uint32_t node;
        uint32_t depth;
        std::vector<uint32_t> list;
    };
    std::vector<Work> stack;
    std::vector<uint32_t> node_polygons;  // indices into polygons, node by node
    nodes.emplace_back();
    stack.push_back({0, 1, std::move(all)});
    while (!stack.empty()) {
        Work work = std::move(stack.back());
        stack.pop_back();
        stats.depth = std::max(stats.depth, work.depth);
        const uint32_t splitter = choose_splitter(work.list, params);
        const glm::dvec4 plane = triangles[polygons[work.list[splitter]].triangle].plane;
        std::vector<uint32_t> front, back;
        const uint32_t first_polygon = uint32_t(node_polygons.size());
        for (size_t k = 0; k < work.list.size(); ++k) {
            const uint32_t index = work.list[k];
            const Side side = k == splitter ? Side::kOn : classify(polygons[index], plane);
            switch (side) {
                case Side::kOn: node_polygons.push_back(index); break;
                case Side::kFront: front.push_back(index); break;
                case Side::kBack: back.push_back(index); break;
                case Side::kSpanning: split(index, plane, front, back, params); break;
            }
        }
        work.list = std::vector<uint32_t>();  // free it before the children's lists grow
        // Polygons of one plane that overlap meet at equal depths: the plain z-buffer keeps the
        // lower instance, then the lower face, so they are kept in that order (and drawn so that
        // it wins).
        std::sort(node_polygons.begin() + first_polygon, node_polygons.end(), [&](uint32_t a, uint32_t b) {
            const Triangle &ta = triangles[polygons[a].triangle], &tb = triangles[polygons[b].triangle];
            return ta.instance != tb.instance ? ta.instance < tb.instance : ta.face < tb.face;
        });
        Node& node = nodes[work.node];
        node.plane = plane;
        node.first_polygon = first_polygon;
        node.polygon_count = uint32_t(node_polygons.size()) - first_polygon;
        for (std::vector<uint32_t>* side : {&back, &front}) {
            if (side->empty()) continue;
            const uint32_t child = uint32_t(nodes.size());
            (side == &front ? nodes[work.node].front : nodes[work.node].back) = child;
            nodes.emplace_back();
            stack.push_back({child, work.depth + 1, std::move(*side)});
        }
    }
    lay_out(node_polygons);
}

// Every subtree becomes one contiguous range of each array, which the walk reads, in either order
// of the children, with far fewer cache misses than in the order the build made things; the
// corners and cuts of polygons that were cut again are dropped.
void Tree::lay_out(const std::vector<uint32_t>& node_polygons) {
    size_t corner_total = 0, cut_total = 0;
    for (uint32_t index : node_polygons) {
        corner_total += polygons[index].corner_count;
        cut_total += polygons[index].cut_count;
    }
    std::vector<Node> out_nodes;
    std::vector<Triangle> out_triangles;
    std::vector<Polygon> out_polygons;
    std::vector<glm::dvec3> out_corners;
    std::vector<Cut> out_cuts;
    out_nodes.reserve(nodes.size());
    out_triangles.reserve(triangles.size());
    out_polygons.reserve(node_polygons.size());
    out_corners.reserve(corner_total);
    out_cuts.reserve(cut_total);
    std::vector<uint32_t> new_triangle(triangles.size(), kNoNode);
    struct Visit {
        uint32_t node;    // in nodes
        uint32_t parent;  // in out_nodes
        bool front;       // the parent's front child
    };
    std::vector<Visit> stack{{0, kNoNode, false}};
    while (!stack.empty()) {
        const Visit visit = stack.back();
        stack.pop_back();
        const uint32_t index = uint32_t(out_nodes.size());
        if (visit.parent != kNoNode)
            (visit.front ? out_nodes[visit.parent].front : out_nodes[visit.parent].back) = index;
        const Node& old = nodes[visit.node];
        Node node = old;
        node.front = node.back = kNoNode;
        node.first_polygon = uint32_t(out_polygons.size());
        for (uint32_t k = 0; k < old.polygon_count; ++k) {
            const Polygon& p = polygons[node_polygons[old.first_polygon + k]];
            uint32_t& triangle = new_triangle[p.triangle];
            if (triangle == kNoNode) {
                triangle = uint32_t(out_triangles.size());
                out_triangles.push_back(triangles[p.triangle]);
            }
            out_polygons.push_back(
                {uint32_t(out_corners.size()), p.corner_count, triangle, uint32_t(out_cuts.size()), p.cut_count});
            out_corners.insert(out_corners.end(), corners.begin() + p.first_corner,
                               corners.begin() + p.first_corner + p.corner_count);
            out_cuts.insert(out_cuts.end(), cuts.begin() + p.first_cut, cuts.begin() + p.first_cut + p.cut_count);
        }
        out_nodes.push_back(node);
        if (old.back != kNoNode) stack.push_back({old.back, index, false});
        if (old.front != kNoNode) stack.push_back({old.front, index, true});
    }
    nodes = std::move(out_nodes);
    triangles = std::move(out_triangles);
    polygons = std::move(out_polygons);
    corners = std::move(out_corners);
    cuts = std::move(out_cuts);
}

}  // namespace bsp
