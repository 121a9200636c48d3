// TopologicalChangeProcessor's INCISE= lines (SOFA's processTopologicalChanges, its INCISE=
// branch, and getValuesInLine): reading them, and cutting the topology along them.
//
// A line is cut first on a copy of the topology and of its state's positions (the same
// container and state follower code), then on the topology itself only when the copy's cut
// succeeded: a bad line (a point in no triangle, a path SOFA cannot split) changes nothing.
#include "scene/topology/topological_change_processor.hpp"

#include "penalty/core/error.hpp"
#include "penalty/mechanics/state_topology.hpp"

#include "io/text.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <optional>

namespace penalty::scene {

namespace {

/// The numbers of a line, read as a scene's attributes are (io::detail::parse_double, within
/// io::detail::kMaxMagnitude); throws naming the first that is not one.
std::vector<double> numbers_of(const std::string& line, const std::string& at) {
    std::vector<double> out;
    for (const std::string_view v : io::detail::split_blanks(line)) {
        const std::optional<double> x = io::detail::parse_double(v);
        if (!x) throw_invalid_argument(at, ": '", v, "' is not a number");
        if (const auto problem = io::detail::magnitude_problem(*x))
            throw_invalid_argument(at, ": '", v, "': ", *problem);
        out.push_back(*x);
    }
    return out;
}

}  // namespace

// `INCISE= n`, then a line of n points: x y z each (the coordinates form), or t x y z each (the
// index form, t a triangle). SOFA's getValuesInLine accepts other counts with a warning and reads
// them as it can; penalty refuses them.
IncisionLine TopologyChangeFile::read_incision(std::size_t i, std::istringstream& in) const {
    long long n = -1;
    if (!(in >> n) || n < 2 || n > 10'000'000)
        throw_invalid_argument(at(i), ": 'INCISE=' needs the count of the cut's points (2 or more)");
    if (i + 1 >= lines_.size()) throw_invalid_argument(at(i), ": 'INCISE= ", n, "' has no line of points after it");
    const std::vector<double> values = numbers_of(lines_[i + 1], at(i + 1));
    const auto count = std::size_t(n);
    if (values.size() != 3 * count && values.size() != 4 * count)
        throw_invalid_argument(at(i + 1), ": ", values.size(), " values for 'INCISE= ", n, "': expected ", 3 * count,
                               " (x y z per point) or ", 4 * count, " (triangle x y z per point)");
    const bool indexed = values.size() == 4 * count;
    IncisionLine line;
    for (std::size_t k = 0; k < count; ++k) {
        const std::size_t o = indexed ? 4 * k + 1 : 3 * k;
        if (indexed) {
            const double t = values[4 * k];
            if (t < 0 || t != std::floor(t) || t > double(std::numeric_limits<ElementId>::max()))
                throw_invalid_argument(at(i + 1), ": point ", k + 1, ": '", t, "' is not a triangle index");
            line.triangles.push_back(ElementId(t));
        }
        line.points.emplace_back(values[o], values[o + 1], values[o + 2]);
    }
    return line;
}

const IncisionLine& TopologyChangeFile::incision_at(std::size_t i) const {
    const auto it = std::lower_bound(incisions_.begin(), incisions_.end(), i,
                                     [](const IncisionRecord& r, std::size_t line) { return r.line < line; });
    PENALTY_DEMAND(it != incisions_.end() && it->line == i);
    return it->cut;
}

std::vector<std::pair<double, IncisionLine>> TopologyChangeFile::timed_incisions() const {
    std::vector<std::pair<double, IncisionLine>> out;
    out.reserve(incisions_.size());
    for (const IncisionRecord& r : incisions_) {
        // a second INCISE= line of a block follows the first one's points, not its T= line
        if (!r.block_time)
            throw_invalid_argument(at(r.line), ": with saveIndicesAtInit an INCISE= line must follow its T= line");
        out.emplace_back(*r.block_time, r.cut);
    }
    return out;
}

void TopologicalChangeProcessorSource::save_incisions_once() {
    const DynamicTopology& t = *target_;
    if (t.geometry == nullptr)
        fail(0, std::string("INCISE= needs the positions of a Vec3 state in the node of '") + t.path + "'");
    try {
        saved_ = save_incisions(*t.container, t.geometry->position, file_->timed_incisions());
    } catch (const std::invalid_argument& e) {
        fail(0, std::string("saveIndicesAtInit: ") + e.what());
    }
}

/// The saved cut of time `time` (findIndexInListOfTime: within 1e-10), or -1.
int TopologicalChangeProcessorSource::saved_index(double time) const {
    for (std::size_t i = 0; saved_ && i < saved_->size(); ++i)
        if (std::fabs(time - (*saved_)[i].time) < 1e-10) return int(i);
    return -1;
}

// The INCISE= branch of processTopologicalChanges, line after line (saveIndicesAtInit:
// inciseWithSavedIndices, the saved cut of this time).
void TopologicalChangeProcessorSource::incise(const std::vector<Command>& commands, double time) {
    TopologyContainer& c = *target_->container;
    for (const Command& cmd : commands) {
        if (c.level() != ElementType::triangle)
            fail(cmd.line, std::string("INCISE= cuts a triangle topology; '") + target_->path + "' keeps " +
                               element_type_name(c.level()));
        if (target_->geometry == nullptr)
            fail(cmd.line,
                 std::string("INCISE= needs the positions of a Vec3 state in the node of '") + target_->path + "'");
        try {
            runtime_->check_can_change(*target_);
        } catch (const std::invalid_argument& e) {
            fail(cmd.line, e.what());
        }
        const Vec3Object& state = *target_->geometry;
        // the cut on a copy first: nothing changes when it fails
        IncisionOutcome trial;
        try {
            MeshTopology copy = c.mesh();
            TopologyContainer scratch(copy, ElementType::triangle, c.name(), c.options());
            Vec3Object positions("incision trial");
            positions.position = state.position;
            positions.rest_position = state.rest_position;
            StateTopologyFollower<Vec3Types> follower(positions);
            scratch.add_state_follower(follower);
            if (saved_) {
                std::vector<SavedIncision> saved = *saved_;
                trial = saved_index(time) < 0
                            ? IncisionOutcome{}
                            : incise_saved(scratch, positions.position, saved, std::size_t(saved_index(time)),
                                           epsilon_snap_path_, epsilon_snap_border_);
            } else {
                trial = incise_line(scratch, positions.position, cmd.cut, epsilon_snap_path_, epsilon_snap_border_);
            }
        } catch (const std::invalid_argument& e) {
            fail(cmd.line + 1, std::string("INCISE=: ") + e.what());
        }
        const auto refusal = [&](const IncisionOutcome& o) {
            const std::size_t k = std::min(std::size_t(o.refused_segment), cmd.cut.points.size() - 1);
            std::ostringstream what;
            what.precision(17);
            const Vec3 &a = cmd.cut.points[k - 1], &b = cmd.cut.points[k];
            what << "INCISE=: segment " << k << " (from " << a[0] << " " << a[1] << " " << a[2] << " to " << b[0] << " "
                 << b[1] << " " << b[2] << ") does not reach its end point across the surface of '" << target_->path
                 << "' (it leaves it, or stays in one triangle)";
            return what.str();
        };
        if (trial.refused_segment >= 0 && refuse_invalid_incision_) fail(cmd.line + 1, refusal(trial));
        if (saved_ && saved_index(time) < 0) {
            std::cerr << "penalty: warning: " << component_->file << ":" << component_->line << ": "
                      << component_->describe() << ": " << file_->at(cmd.line)
                      << ": no saved cut at the time t = " << time
                      << " (within 1e-10), nothing cut, as SOFA's inciseWithSavedIndices\n";
            continue;
        }
        const IncisionOutcome done =
            saved_ ? incise_saved(c, state.position, *saved_, std::size_t(saved_index(time)), epsilon_snap_path_,
                                  epsilon_snap_border_)
                   : incise_line(c, state.position, cmd.cut, epsilon_snap_path_, epsilon_snap_border_);
        if (done.refused_segment >= 0)
            std::cerr << "penalty: warning: " << component_->file << ":" << component_->line << ": "
                      << component_->describe() << ": " << file_->at(cmd.line + 1) << ": " << refusal(done)
                      << "; the line's later segments are skipped, as SOFA's processTopologicalChanges does "
                         "(--fix-sofa-quirk incision_invalid_path: an error)\n";
    }
}

}  // namespace penalty::scene
