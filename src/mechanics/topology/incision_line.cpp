// One INCISE= line of SOFA's TopologicalChangeProcessor::processTopologicalChanges: the segments
// between its points cut in turn, each continuing from where the previous cut ended.
#include "penalty/core/error.hpp"
#include "penalty/mechanics/triangle_incision.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace penalty {

namespace {

std::string describe(std::size_t k, const Vec3& p) {
    std::ostringstream out;
    out.precision(17);
    out << "point " << k + 1 << " (" << p[0] << " " << p[1] << " " << p[2] << ")";
    return out.str();
}

/// One segment of a cut, the body of SOFA's INCISE= loop (TopologicalChangeProcessor::
/// processTopologicalChanges): computeIntersectedObjectsList, SplitAlongPath, InciseAlongEdgeList.
/// False when SOFA skips the segment (no path); `a_last` becomes the cut's last end point;
/// `segment` names the segment in errors.
bool cut_segment(TriangleIncision& incision, PointId& a_last, Vec3& a, Vec3& b, ElementId& ta, ElementId& tb,
                 const std::string& segment, double epsilon_path, double epsilon_border) {
    std::vector<IncisionPathElement> path;
    if (!incision.intersected_objects(a_last, a, b, ta, tb, path)) return false;
    std::vector<ElementId> new_edges;
    if (incision.split_along_path(a_last, a, -1, b, path, new_edges, epsilon_path, epsilon_border) < 0)
        throw_invalid_argument(segment, ": its path cannot be split (SOFA's SplitAlongPath refuses it)");
    std::vector<PointId> new_points, end_points;
    bool reach_border = false;
    if (!incision.incise_along_edge_list(new_edges, new_points, end_points, reach_border))
        throw_invalid_argument(segment, ": its edges cannot be duplicated (SOFA's InciseAlongEdgeList refuses them)");
    if (!end_points.empty()) a_last = end_points.back();
    return true;
}

}  // namespace

IncisionOutcome incise_line(TopologyContainer& container, const std::vector<Vec3>& positions, const IncisionLine& line,
                            double epsilon_path, double epsilon_border) {
    if (container.level() != ElementType::triangle)
        throw_invalid_argument("an incision needs a triangle topology; '", container.name(), "' keeps ",
                               element_type_name(container.level()));
    TriangleIncision incision(container, positions);
    const bool indexed = !line.triangles.empty();
    const auto triangle_of = [&](std::size_t k) {
        const ElementId t = indexed ? line.triangles[k] : incision.find_triangle(line.points[k]);
        if (indexed && (t < 0 || std::size_t(t) >= container.count(ElementType::triangle)))
            throw_invalid_argument(describe(k, line.points[k]), ": triangle ", t, " does not exist (the topology '",
                                   container.name(), "' has ", container.count(ElementType::triangle), ")");
        if (t < 0)
            throw_invalid_argument(describe(k, line.points[k]), " is in no triangle of the topology '",
                                   container.name(), "'");
        return t;
    };
    // every point checked before the first cut (SOFA finds each one's triangle when it cuts to it)
    for (std::size_t k = 0; k < line.points.size(); ++k) (void)triangle_of(k);
    IncisionOutcome outcome;
    ElementId ta = triangle_of(0);
    Vec3 a = line.points[0];
    PointId a_last = -1;
    for (std::size_t k = 1; k < line.points.size(); ++k) {
        Vec3 b = line.points[k];
        ElementId tb = triangle_of(k);
        if (k > 1) {
            // SOFA reads the state at its last end point (none when the cut reached the border:
            // SOFA reads past the state's end)
            if (a_last < 0)
                throw_invalid_argument("segment ", k, " (", describe(k - 1, line.points[k - 1]), " to ", describe(k, b),
                                       ") continues a cut that ended on the border");
            a = positions[std::size_t(a_last)];
        }
        const std::string segment =
            "segment " + std::to_string(k) + " (" + describe(k - 1, line.points[k - 1]) + " to " + describe(k, b) + ")";
        if (!cut_segment(incision, a_last, a, b, ta, tb, segment, epsilon_path, epsilon_border)) {
            outcome.refused_segment = int(k);
            return outcome;
        }
        ta = tb;
        ++outcome.segments_cut;
    }
    return outcome;
}

}  // namespace penalty

namespace penalty {

namespace {

/// TriangleIncisionInformation::computeCoordinates: Σ x(t_k) b_k, from zero. False when a
/// point's triangle is past the topology's end (its coordinates stay 0; SOFA reads past the list).
bool compute_coordinates(SavedIncision& s, const MeshTopology& m, const std::vector<Vec3>& x) {
    s.coordinates.assign(s.triangles.size(), Vec3::Zero());
    bool ok = true;
    for (std::size_t j = 0; j < s.triangles.size(); ++j) {
        const ElementId t = s.triangles[j];
        if (t < 0 || std::size_t(t) >= m.triangles().size()) {
            ok = false;
            continue;
        }
        const Triangle& tri = m.triangles()[std::size_t(t)];
        for (std::size_t k = 0; k < 3; ++k) s.coordinates[j] += x[std::size_t(tri[k])] * s.barycentric[j][k];
    }
    return ok;
}

}  // namespace

std::vector<SavedIncision> save_incisions(TopologyContainer& container, const std::vector<Vec3>& positions,
                                          const std::vector<std::pair<double, IncisionLine>>& lines) {
    if (container.level() != ElementType::triangle)
        throw_invalid_argument("an incision needs a triangle topology; '", container.name(), "' keeps ",
                               element_type_name(container.level()));
    const TriangleIncision incision(container, positions);
    const auto locate = [&](const Vec3& p, std::size_t k) {
        const ElementId t = incision.find_triangle(p);
        if (t < 0)
            throw_invalid_argument(describe(k, p), " is in no triangle of the topology '", container.name(), "'");
        return t;
    };
    std::vector<SavedIncision> saved;
    for (const auto& [time, line] : lines) {
        auto it = std::find_if(saved.begin(), saved.end(),
                               [when = time](const SavedIncision& s) { return std::fabs(when - s.time) < 1e-10; });
        if (it == saved.end()) {
            saved.push_back({time, {}, {}, {}});
            it = saved.end() - 1;
        }
        for (std::size_t k = 0; k < line.points.size(); ++k) {
            const ElementId t = line.triangles.empty() ? locate(line.points[k], k) : line.triangles[k];
            if (t < 0 || std::size_t(t) >= container.count(ElementType::triangle))
                throw_invalid_argument(describe(k, line.points[k]), ": triangle ", t, " does not exist");
            it->triangles.push_back(t);
            it->barycentric.push_back(incision.barycentric(t, line.points[k]));
        }
    }
    for (std::size_t i = 0; i < saved.size(); ++i) {
        SavedIncision& s = saved[i];
        compute_coordinates(s, container.mesh(), positions);
        if (i == 0 || s.coordinates.size() < 2) continue;
        const Vec3& previous_end = saved[i - 1].coordinates.back();
        bool equal = true;
        for (int j = 0; j < 3; ++j) equal = equal && std::fabs(s.coordinates.front()[j] - previous_end[j]) < 1e-5;
        if (!equal) continue;
        Vec3 direction = s.coordinates[1] - s.coordinates[0];
        direction *= 1e-5;
        const Vec3 moved = s.coordinates[0] + direction;
        s.triangles[0] = locate(moved, 0);
        s.barycentric[0] = incision.barycentric(s.triangles[0], moved);
        compute_coordinates(s, container.mesh(), positions);
    }
    return saved;
}

IncisionOutcome incise_saved(TopologyContainer& container, const std::vector<Vec3>& positions,
                             std::vector<SavedIncision>& saved, std::size_t index, double epsilon_path,
                             double epsilon_border) {
    TriangleIncision incision(container, positions);
    for (std::size_t i = 0; i < saved.size(); ++i)
        if (!compute_coordinates(saved[i], container.mesh(), positions) && i == index)
            throw_invalid_argument("a point of the cut at t = ", saved[i].time, " has no triangle any more");
    const std::vector<Vec3> coordinates = saved[index].coordinates;
    IncisionOutcome outcome;
    if (coordinates.empty()) return outcome;
    ElementId ta = saved[index].triangles[0];
    Vec3 a = coordinates[0];
    PointId a_last = -1;
    for (std::size_t k = 1; k < coordinates.size(); ++k) {
        ElementId tb = saved[index].triangles[k];
        Vec3 b = coordinates[k];
        if (k > 1) {
            if (a_last < 0)
                throw_invalid_argument("segment ", k, " (", describe(k, b),
                                       ") continues a cut that ended on the border");
            a = positions[std::size_t(a_last)];
        }
        if (ta < 0 || tb < 0 || std::size_t(std::max(ta, tb)) >= container.count(ElementType::triangle))
            throw_invalid_argument("segment ", k, " (", describe(k, b), "): a saved point has no triangle any more");
        const std::string segment = "segment " + std::to_string(k) + " (" + describe(k, b) + ")";
        if (!cut_segment(incision, a_last, a, b, ta, tb, segment, epsilon_path, epsilon_border)) {
            outcome.refused_segment = int(k);
            return outcome;
        }
        ta = tb;
        ++outcome.segments_cut;
        container.notify_ending_event();
        // updateTriangleIncisionInformation: every saved point's triangle found again (its
        // previous one kept when it still holds it), with its barycentric coordinates there
        for (SavedIncision& s : saved)
            for (std::size_t j = 0; j < s.triangles.size() && j < s.coordinates.size(); ++j) {
                const ElementId t = incision.find_triangle(s.coordinates[j], s.triangles[j]);
                if (t < 0) break;
                s.triangles[j] = t;
                s.barycentric[j] = incision.barycentric(t, s.coordinates[j]);
            }
    }
    return outcome;
}

}  // namespace penalty
