#pragma once
// TopologicalChangeProcessor and TopologyBoundingTrasher as change sources (see
// topological_change_processor.cpp).
#include "scene/topology/topology_runtime.hpp"

#include "penalty/mechanics/triangle_incision.hpp"

#include <array>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace penalty::scene {

/// A TopologicalChangeProcessor file: its lines and SOFA's reading state (readNext).
class TopologyChangeFile {
public:
    /// `name`: the file as errors name it. Throws std::invalid_argument naming name:line for a
    /// malformed command.
    TopologyChangeFile(const std::string& text, std::string name);

    struct Command {
        std::size_t line = 0;            ///< the command's line (0-based); its values are on the next
        std::optional<ElementType> add;  ///< ADD= of this type; none: REMOVE=
        std::vector<ElementId> values;   ///< indices (REMOVE=) or vertices (ADD=), missing ones 0
        bool incise = false;             ///< INCISE=: `cut` holds its points
        IncisionLine cut;
    };
    /// readNext: the lines to apply at `time` (SOFA's validLines), advancing the reading state.
    std::vector<std::size_t> read_next(double time, bool loop);
    /// The commands of those lines.
    [[nodiscard]] std::vector<Command> commands(const std::vector<std::size_t>& lines) const;
    /// "file:line" (1-based) of line `line` (0-based).
    [[nodiscard]] std::string at(std::size_t line) const;
    /// Remarks for `penalty info` (counts SOFA completes with zeros).
    [[nodiscard]] const std::vector<std::string>& notes() const { return notes_; }
    /// True when the file has INCISE= lines.
    [[nodiscard]] bool has_incisions() const { return !incisions_.empty(); }
    /// saveIndices: each INCISE= line with the time of the T= line just before it (blank lines
    /// aside). Throws std::invalid_argument naming the line for an INCISE= line without one (as a
    /// second INCISE= line in a block: SOFA skips it with an error).
    [[nodiscard]] std::vector<std::pair<double, IncisionLine>> timed_incisions() const;

private:
    /// An INCISE= command as check() read it.
    struct IncisionRecord {
        std::size_t line = 0;              ///< the INCISE= line (0-based); its points are on the next
        IncisionLine cut;                  ///< its points
        std::optional<double> block_time;  ///< the time of the T= line right before it, if it is
    };
    void check();
    /// A REMOVE= or ADD= command at line i, its values on the next line.
    void check_edit(std::size_t i, const std::string& cmd, std::istringstream& in);
    /// An INCISE= command at line i: `INCISE= n`, then n points (x y z, or triangle x y z).
    [[nodiscard]] IncisionLine read_incision(std::size_t i, std::istringstream& in) const;
    /// The points of the INCISE= command at line i.
    [[nodiscard]] const IncisionLine& incision_at(std::size_t i) const;
    std::string read_line();
    std::string name_;
    std::vector<std::string> lines_;
    std::vector<std::string> notes_;
    std::size_t pos_ = 0;
    bool eof_ = false;
    double next_time_ = 0, loop_time_ = 0;
    std::string cmd_;                        ///< SOFA's `cmd`, kept from line to line
    std::vector<IncisionRecord> incisions_;  ///< in the file's order
};

class TopologicalChangeProcessorSource final : public TopologyChangeSource {
public:
    TopologicalChangeProcessorSource(const io::SceneComponent& component, DynamicTopology& target,
                                     const TopologyRuntime& runtime);
    void begin_step(double time) override;

    // file mode
    std::optional<TopologyChangeFile> file_;
    double shift_ = 0;
    bool loop_ = false;
    // useDataInputs mode
    bool data_inputs_ = false;
    double time_to_remove_ = 0, interval_ = 0;
    struct RemovalList {
        ElementType type;
        std::size_t line = 0;                            ///< the attribute's line (errors)
        std::vector<ElementId> values;                   ///< given inline
        std::function<std::vector<ElementId>()> source;  ///< or computed when used (a linked ROI)
    };
    std::vector<RemovalList> lists_;  ///< hexahedra, tetrahedra, quads, triangles, edges, points
    /// SofaQuirkFixes::fix_topology_removal_out_of_range: a removed element past the end is an
    /// error; false (SOFA): it is dropped with a warning on stderr.
    bool refuse_out_of_range_ = false;
    /// INCISE=: SOFA's snapping thresholds (the file mode's processTopologicalChanges passes 0.1
    /// and 0.25 whatever the attributes say), and SofaQuirkFixes::fix_incision_invalid_path (a
    /// refused segment is an error; false (SOFA): the rest of its line is skipped with a warning).
    double epsilon_snap_path_ = 0.1, epsilon_snap_border_ = 0.25;
    bool refuse_invalid_incision_ = false;
    /// saveIndicesAtInit: the cuts located at the first step (SOFA's init), then followed.
    bool save_indices_at_init_ = false;
    std::optional<std::vector<SavedIncision>> saved_;

private:
    using Command = TopologyChangeFile::Command;
    void remove_data_inputs(double time);
    /// The INCISE= commands of a step, in order (src/scene/topology/incision_commands.cpp): each
    /// run first on a copy of the topology and its positions, then on the topology when it
    /// succeeds, so that a bad line changes nothing.
    void incise(const std::vector<Command>& commands, double time);
    /// saveIndicesAtInit: the file's cuts located on the topology as it is (the first step).
    void save_incisions_once();
    [[nodiscard]] int saved_index(double time) const;
    [[noreturn]] void fail(std::size_t line, const std::string& what) const;
    /// Drops a removal's indices at or past `count` with a warning (SOFA's modifiers).
    void drop_out_of_range(Command& cmd, ElementType type, std::size_t count) const;
    template <std::size_t N>
    static std::vector<std::array<PointId, N>> elements(const std::vector<ElementId>& flat) {
        std::vector<std::array<PointId, N>> out(flat.size() / N);
        for (std::size_t i = 0; i < out.size() * N; ++i) out[i / N][i % N] = flat[i];
        return out;
    }
    const io::SceneComponent* component_;
    DynamicTopology* target_;
    const TopologyRuntime* runtime_;
};

}  // namespace penalty::scene
