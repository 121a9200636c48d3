#include "penalty/mechanics/subset_topology.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>

namespace penalty {

namespace {

/// The region test of SubsetTopology::isPointInROI for region number `r`.
class Region {
public:
    explicit Region(const SubsetRegion& region) : region_(region) {
        if (!region.centers.empty() && region.centers.size() != region.radii.size())
            throw_invalid_argument("SubsetTopology: ", region.centers.size(), " sphere centers but ",
                                   region.radii.size(), " radii");
    }
    [[nodiscard]] std::size_t count() const {
        return region_.centers.empty() ? region_.boxes.size() : region_.centers.size();
    }
    [[nodiscard]] bool contains(const Vec3& p, std::size_t r) const {
        if (region_.centers.empty()) return region_.boxes[r].contains(p);
        return !((p - region_.centers[r]).norm() > region_.radii[r]);
    }

private:
    const SubsetRegion& region_;
};

template <std::size_t N>
void check_elements(const std::vector<std::array<PointId, N>>& elements, std::size_t num_points, const char* what) {
    for (std::size_t e = 0; e < elements.size(); ++e)
        for (const PointId v : elements[e])
            if (v < 0 || static_cast<std::size_t>(v) >= num_points)
                throw_invalid_argument("SubsetTopology: ", what, " ", e, " uses point ", v, " out of range (",
                                       num_points, " points)");
}

/// SubsetTopology with `tetrahedraInput`: the listed tetrahedra are inside; the point lists are
/// rebuilt from the tetrahedra's vertices in order of first use (SOFA keeps `indices` from the
/// region test and appends); `local_index`: the inside points' local numbers (localIndices).
void split_listed_tetrahedra(const SubsetInput& in, bool local, std::vector<PointId>& local_index, SubsetOutput& out) {
    const auto& x0 = in.positions;
    const std::vector<PointId>& listed = *in.tetrahedra_input;
    std::vector<bool> seen_in(x0.size(), false), seen_out(x0.size(), false);
    std::vector<PointId> local_out(x0.size(), 0);
    out.points_in.clear();
    out.points_out.clear();
    PointId count_in = 0, count_out = 0;
    for (std::size_t e = 0; e < in.tetrahedra.size(); ++e) {
        Tetrahedron t = in.tetrahedra[e];
        const bool inside = std::find(listed.begin(), listed.end(), static_cast<PointId>(e)) != listed.end();
        for (PointId& v : t) {
            const auto k = static_cast<std::size_t>(v);
            if (inside && !seen_in[k]) {
                seen_in[k] = true;
                out.indices.push_back(v);
                out.points_in.push_back(x0[k]);
                if (local) local_index[k] = count_in++;
            } else if (!inside && !seen_out[k]) {
                seen_out[k] = true;
                out.points_out.push_back(x0[k]);
                if (local) local_out[k] = count_out++;
            }
            if (local) v = inside ? local_index[k] : local_out[k];
        }
        if (inside) {
            out.tetrahedron_indices.push_back(static_cast<PointId>(e));
            out.tetrahedra_in.push_back(t);
        } else {
            out.tetrahedra_out.push_back(t);
        }
    }
}

}  // namespace

SubsetOutput select_subset(const SubsetInput& in, const SubsetRegion& region_spec) {
    const Region region(region_spec);
    const auto& x0 = in.positions;
    check_elements(in.edges, x0.size(), "edge");
    check_elements(in.triangles, x0.size(), "triangle");
    check_elements(in.quads, x0.size(), "quad");
    check_elements(in.tetrahedra, x0.size(), "tetrahedron");
    check_elements(in.hexahedra, x0.size(), "hexahedron");
    const std::size_t regions = region.count();
    const auto point_in = [&](PointId v, std::size_t r) { return region.contains(x0[static_cast<std::size_t>(v)], r); };
    // an element is inside when all its vertices are inside one same region (isTriangleInROI, ...)
    const auto element_in = [&](const auto& element) {
        for (std::size_t r = 0; r < regions; ++r)
            if (std::all_of(element.begin(), element.end(), [&](PointId v) { return point_in(v, r); })) return true;
        return false;
    };

    SubsetOutput out;
    const bool local = in.local_indices;
    std::vector<PointId> local_index;  // SOFA's localIndices
    std::vector<PointId> border;       // SOFA's listOnBorder, in order of discovery
    if (local) {
        // findVertexOnBorder on the triangles, or the tetrahedra when there are some, first region only
        const auto find_border = [&](const auto& element) {
            bool any_in = false, any_out = false;
            for (const PointId v : element) (point_in(v, 0) ? any_in : any_out) = true;
            if (!(any_in && any_out)) return;
            for (const PointId v : element)
                if (point_in(v, 0) && std::find(border.begin(), border.end(), v) == border.end()) border.push_back(v);
        };
        if (regions > 0) {
            if (in.tetrahedra.empty()) std::for_each(in.triangles.begin(), in.triangles.end(), find_border);
            else std::for_each(in.tetrahedra.begin(), in.tetrahedra.end(), find_border);
        }
        std::sort(border.begin(), border.end());
        local_index.assign(x0.size(), 0);
        out.border_count = border.size();
        out.indices.assign(border.size(), 0);
        out.points_in.assign(border.size(), Vec3::Zero());
        out.points_out.assign(border.size(), Vec3::Zero());
    }

    // points: border points take the first places of both lists, then inside / outside in order
    PointId next_in = static_cast<PointId>(out.border_count), next_out = next_in, next_border = 0;
    std::size_t border_cursor = 0;
    for (std::size_t i = 0; i < x0.size(); ++i) {
        const auto id = static_cast<PointId>(i);
        if (local && border_cursor < border.size() && border[border_cursor] == id) {
            local_index[i] = next_border;
            out.indices[static_cast<std::size_t>(next_border)] = id;
            out.points_in[static_cast<std::size_t>(next_border)] = x0[i];
            out.points_out[static_cast<std::size_t>(next_border)] = x0[i];
            ++next_border;
            ++border_cursor;
            continue;
        }
        bool inside = false;
        for (std::size_t r = 0; r < regions && !inside; ++r) inside = point_in(id, r);
        if (inside) {
            out.indices.push_back(id);
            out.points_in.push_back(x0[i]);
            if (local) local_index[i] = next_in++;
        } else {
            out.points_out.push_back(x0[i]);
            if (local) local_index[i] = next_out++;
        }
    }

    const auto renumber = [&](auto element) {
        if (local)
            for (PointId& v : element) v = local_index[static_cast<std::size_t>(v)];
        return element;
    };
    const auto split = [&](const auto& elements, std::vector<PointId>& indices, auto& inside, auto& outside) {
        for (std::size_t e = 0; e < elements.size(); ++e) {
            if (element_in(elements[e])) {
                indices.push_back(static_cast<PointId>(e));
                inside.push_back(renumber(elements[e]));
            } else {
                outside.push_back(renumber(elements[e]));
            }
        }
    };
    split(in.edges, out.edge_indices, out.edges_in, out.edges_out);
    split(in.triangles, out.triangle_indices, out.triangles_in, out.triangles_out);
    split(in.quads, out.quad_indices, out.quads_in, out.quads_out);

    if (!in.tetrahedra_input) {
        split(in.tetrahedra, out.tetrahedron_indices, out.tetrahedra_in, out.tetrahedra_out);
    } else {
        split_listed_tetrahedra(in, local, local_index, out);
    }
    split(in.hexahedra, out.hexahedron_indices, out.hexahedra_in, out.hexahedra_out);
    return out;
}

}  // namespace penalty
