// SOFA's TopologicalChangeProcessor (handleEvent at AnimateBeginEvent, readNext,
// processTopologicalChanges) and TopologyBoundingTrasher (filterElementsToRemove at
// AnimateEndEvent), as change sources of the scene's TopologyRuntime.
//
// The file is read once, at build: its syntax is checked there (file, line); each step's lines are
// then chosen as SOFA's readNext chooses them (the last `T=` block whose time is reached, the
// others skipped; `loop` rewinds) and applied as its processTopologicalChanges applies them. A
// step's commands are all checked against the topology (indices in range, none repeated) before
// the first is applied: a step changes the topology whole or not at all.
#include "scene/topology/topological_change_processor.hpp"
#include "penalty/mechanics/regions.hpp"
#include "penalty/mechanics/regions_of_interest.hpp"

#include "penalty/core/error.hpp"
#include "penalty/io/data_path.hpp"

#include "io/text.hpp"

#include <cfloat>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

namespace penalty::scene {

namespace {

/// The element type an ADD= keyword names, as processTopologicalChanges reads it.
std::optional<ElementType> added_type(const std::string& keyword) {
    if (keyword == "Edge" || keyword == "Edges") return ElementType::edge;
    if (keyword == "Triangle" || keyword == "Triangles") return ElementType::triangle;
    if (keyword == "Quad" || keyword == "Quads") return ElementType::quad;
    if (keyword == "Tetrahedron" || keyword == "Tetrahedra") return ElementType::tetrahedron;
    if (keyword == "Hexahedron" || keyword == "Hexahedra") return ElementType::hexahedron;
    return std::nullopt;
}

}  // namespace

// ---- the file -----------------------------------------------------------------------------------

TopologyChangeFile::TopologyChangeFile(const std::string& text, std::string name) : name_(std::move(name)) {
    // getline's pieces: a final newline gives one more (empty) line, read with the end of file
    std::size_t start = 0;
    for (;;) {
        const std::size_t end = text.find('\n', start);
        if (end == std::string::npos) {
            lines_.push_back(text.substr(start));
            break;
        }
        lines_.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    check();
}

std::string TopologyChangeFile::at(std::size_t line) const { return name_ + ":" + std::to_string(line + 1); }

// One pass over the lines: every command well formed (`T= time`, `REMOVE= n` then a line,
// `ADD= Type n` then a line of n elements, `INCISE= n` then a line of n points), and each block
// (from one T= to the next) either cuts or removes/adds: penalty applies a step's REMOVE=/ADD=
// lines together before anything else, so it does not order them with cuts.
void TopologyChangeFile::check() {
    std::size_t block = 0;
    std::optional<double> block_time;  // the last T= line's
    bool cuts = false, edits = false;
    std::size_t previous = lines_.size();  // the last non-blank line
    for (std::size_t i = 0; i < lines_.size(); ++i) {
        std::istringstream in(lines_[i]);
        std::string cmd;
        if (!(in >> cmd)) continue;
        std::size_t last = i;  // the command's last line (its values)
        if (cmd == "T=") {
            double t = 0;
            if (!(in >> t) || !std::isfinite(t)) throw_invalid_argument(at(i), ": 'T=' needs a time");
            block = i;
            block_time = t;
            cuts = edits = false;
        } else if (cmd == "REMOVE=" || cmd == "ADD=") {
            check_edit(i, cmd, in);
            edits = true;
            last = i + 1;
        } else if (cmd == "INCISE=") {
            // saveIndices pairs an INCISE= line with the non-blank line before it, when a T= line
            const bool after_time = block_time.has_value() && previous == block;
            incisions_.push_back({i, read_incision(i, in), after_time ? block_time : std::nullopt});
            cuts = true;
            last = i + 1;
        }
        if (cuts && edits)
            throw_invalid_argument(at(i), ": the block of ", at(block),
                                   " mixes INCISE= with REMOVE=/ADD= lines, which penalty does not order (put them "
                                   "in blocks of their own)");
        previous = last;
        i = last;
    }
}

// `REMOVE= n` then a line of n indices, `ADD= Type n` then a line of n elements. (SOFA reads a
// missing index as 0; so does penalty, with a note.)
void TopologyChangeFile::check_edit(std::size_t i, const std::string& cmd, std::istringstream& in) {
    std::string type;
    if (cmd == "ADD=") {
        in >> type;
        if (type == "PointInTriangle" || type == "PointsInTriangle")
            throw_invalid_argument(at(i), ": 'ADD= ", type, "' is not supported by penalty");
        if (!added_type(type))
            throw_invalid_argument(at(i), ": 'ADD= ", type,
                                   "': expected Edges, Triangles, Quads, Tetrahedra or Hexahedra");
    }
    long long n = -1;
    if (!(in >> n) || n < 0 || n > 100'000'000) throw_invalid_argument(at(i), ": '", cmd, "' needs a count");
    if (i + 1 >= lines_.size()) throw_invalid_argument(at(i), ": '", cmd, " ", n, "' has no line of indices after it");
    std::size_t found = 0;
    for (const std::string_view v : io::detail::split_blanks(lines_[i + 1])) {
        const std::optional<std::int64_t> x = io::detail::parse_int(v);
        if (!x || *x < 0 || *x > std::numeric_limits<ElementId>::max())
            throw_invalid_argument(at(i + 1), ": '", v, "' is not an index");
        ++found;
    }
    const std::size_t per = cmd == "ADD=" ? std::size_t(vertices_per_element(*added_type(type))) : 1;
    if (found > std::size_t(n) * per)
        throw_invalid_argument(at(i + 1), ": ", found, " values for '", cmd, type.empty() ? "" : " ", type, " ", n,
                               "'");
    if (found < std::size_t(n) * per)
        notes_.push_back(at(i + 1) + ": " + std::to_string(found) + " values for '" + cmd +
                         (type.empty() ? "" : " " + type) + " " + std::to_string(n) +
                         "': as SOFA, the missing ones read as 0");
}

// getline on the file: a line, and the end of file once the last one is read.
std::string TopologyChangeFile::read_line() {
    const std::string& line = lines_[pos_++];
    eof_ = pos_ == lines_.size();
    return line;
}

// TopologicalChangeProcessor::readNext: the lines of the last block whose time is reached.
std::vector<std::size_t> TopologyChangeFile::read_next(double time, bool loop) {
    std::vector<std::size_t> valid;
    const double epsilon = DBL_EPSILON;
    const auto reached = [&] { return next_time_ < time || std::fabs(next_time_ - time) < epsilon; };
    while (reached()) {
        if (eof_) {
            if (!loop) break;
            pos_ = 0;
            eof_ = false;
            loop_time_ = next_time_;
        }
        const std::size_t index = pos_;
        std::istringstream str(read_line());
        str >> cmd_;  // unchanged on an empty line, as SOFA's
        if (cmd_ == "T=") {
            str >> next_time_;
            next_time_ += loop_time_;
            if (reached()) valid.clear();
        }
        if (reached()) valid.push_back(index);
    }
    return valid;
}

std::vector<TopologyChangeFile::Command> TopologyChangeFile::commands(const std::vector<std::size_t>& lines) const {
    std::vector<Command> out;
    for (std::size_t k = 0; k < lines.size(); ++k) {
        std::istringstream str(lines_[lines[k]]);
        std::string buff;
        str >> buff;
        if (buff == "INCISE=") {
            if (k + 1 >= lines.size()) break;  // its values lie in the next step's lines
            Command c;
            c.line = lines[k];
            c.incise = true;
            c.cut = incision_at(lines[k]);
            out.push_back(std::move(c));
            ++k;
            continue;
        }
        if (buff != "REMOVE=" && buff != "ADD=") continue;
        Command c;
        c.line = lines[k];
        std::size_t per = 1;
        if (buff == "ADD=") {
            std::string type;
            str >> type;
            c.add = added_type(type);
            per = std::size_t(vertices_per_element(*c.add));
        }
        long long n = 0;
        str >> n;
        if (k + 1 >= lines.size()) break;  // its values lie in the next step's lines: SOFA reads past the end
        std::istringstream values(lines_[lines[++k]]);
        c.values.assign(std::size_t(n) * per, 0);
        for (auto& v : c.values) {
            long long x = 0;
            if (!(values >> x)) break;
            v = ElementId(x);
        }
        out.push_back(std::move(c));
    }
    return out;
}

// ---- the component ----------------------------------------------------------------------------

TopologicalChangeProcessorSource::TopologicalChangeProcessorSource(const io::SceneComponent& component,
                                                                   DynamicTopology& target,
                                                                   const TopologyRuntime& runtime)
    : component_(&component), target_(&target), runtime_(&runtime) {}

void TopologicalChangeProcessorSource::drop_out_of_range(Command& cmd, ElementType type, std::size_t count) const {
    // SOFA's *SetTopologyModifier::remove* (edges to hexahedra; not points): an index past the
    // container's end is skipped with a warning, the others are removed
    std::vector<ElementId> dropped;
    std::erase_if(cmd.values, [&](ElementId i) {
        const bool past_end = i >= 0 && std::size_t(i) >= count;
        if (past_end) dropped.push_back(i);
        return past_end;
    });
    if (dropped.empty()) return;
    std::string list;
    for (std::size_t k = 0; k < dropped.size() && k < 5; ++k) list += (k ? ", " : "") + std::to_string(dropped[k]);
    if (dropped.size() > 5) list += ", ...";
    std::cerr << "penalty: warning: " << component_->file << ":" << component_->line << ": " << component_->describe()
              << ": " << file_->at(cmd.line + 1) << ": " << dropped.size() << " " << element_type_name(type)
              << " index(es) past the end of '" << target_->path << "' (" << count << ") not removed (" << list
              << "), as SOFA's modifier skips them (--fix-sofa-quirk topology_removal_out_of_range: an error)\n";
}

void TopologicalChangeProcessorSource::fail(std::size_t line, const std::string& what) const {
    io::throw_element_error(*component_, (file_ ? file_->at(line) + ": " : std::string()) + what);
}

// TopologicalChangeProcessor::handleEvent(AnimateBeginEvent).
void TopologicalChangeProcessorSource::begin_step(double time) {
    if (data_inputs_) return remove_data_inputs(time);
    if (save_indices_at_init_ && !saved_) save_incisions_once();
    const auto lines = file_->read_next(time + shift_, loop_);
    auto commands = file_->commands(lines);
    if (commands.empty()) return;
    if (commands.front().incise) return incise(commands, time);  // a block cuts or edits (check())
    TopologyContainer& c = *target_->container;
    // every command checked first, against the counts the earlier ones leave
    try {
        runtime_->check_can_change(*target_);
    } catch (const std::invalid_argument& e) {
        fail(commands.front().line, e.what());
    }
    std::array<std::size_t, kElementTypeCount> counts{};
    for (int t = 0; t < kElementTypeCount; ++t)
        counts[std::size_t(t)] = c.keeps(ElementType(t)) ? c.count(ElementType(t)) : 0;
    bool removed = false;
    for (Command& cmd : commands) {
        const ElementType type = cmd.add ? *cmd.add : c.level();
        if (!cmd.add && type != ElementType::point && !refuse_out_of_range_)
            drop_out_of_range(cmd, type, counts[std::size_t(type)]);
        if (!c.keeps(type))
            fail(cmd.line, std::string("the topology '") + target_->path + "' has no " + element_type_name(type));
        if (cmd.add) {
            for (std::size_t k = 0; k < cmd.values.size(); ++k)
                if (std::size_t(cmd.values[k]) >= counts[0])
                    fail(cmd.line + 1, "vertex " + std::to_string(cmd.values[k]) + " of new " +
                                           element_type_name(type) + " " +
                                           std::to_string(k / std::size_t(vertices_per_element(type))) +
                                           " does not exist (the topology '" + target_->path + "' has " +
                                           std::to_string(counts[0]) + " points)");
            const std::size_t per = std::size_t(vertices_per_element(type));
            for (std::size_t e = 0; e + per <= cmd.values.size(); e += per)
                for (std::size_t a = 0; a < per; ++a)
                    for (std::size_t b = a + 1; b < per; ++b)
                        if (cmd.values[e + a] == cmd.values[e + b])
                            fail(cmd.line + 1, "new " + std::string(element_type_name(type)) + " " +
                                                   std::to_string(e / per) + " uses vertex " +
                                                   std::to_string(cmd.values[e + a]) + " twice");
            // degenerate new elements (refused by the FEM force fields), checked here while no
            // removal of this step has renumbered the points
            if (!removed) try {
                    TopologyRuntime::check_added(*target_, type, cmd.values);
                } catch (const std::invalid_argument& e) {
                    fail(cmd.line + 1, e.what());
                }
            counts[std::size_t(type)] += cmd.values.size() / std::size_t(vertices_per_element(type));
        } else {
            try {
                std::vector<char> seen(counts[std::size_t(type)], 0);
                for (const ElementId i : cmd.values) {
                    if (i < 0 || std::size_t(i) >= seen.size())
                        throw_invalid_argument(element_type_name(type), " ", i, " does not exist (the topology '",
                                               target_->path, "' has ", seen.size(), ")");
                    if (seen[std::size_t(i)])
                        throw_invalid_argument(element_type_name(type), " ", i, " is listed twice");
                    seen[std::size_t(i)] = 1;
                }
            } catch (const std::invalid_argument& e) {
                fail(cmd.line + 1, e.what());
            }
            try {
                TopologyRuntime::check_keeps_elements(*target_, type, counts[std::size_t(type)] - cmd.values.size());
            } catch (const std::invalid_argument& e) {
                fail(cmd.line + 1, e.what());
            }
            counts[std::size_t(type)] -= cmd.values.size();
            removed = true;
        }
    }
    for (const Command& cmd : commands) {
        if (!cmd.add) {
            c.remove_items(cmd.values);
            continue;
        }
        const ElementType type = *cmd.add;
        switch (type) {
            case ElementType::edge:
                c.add_edges(elements<2>(cmd.values));
                break;
            case ElementType::triangle:
                c.add_triangles(elements<3>(cmd.values));
                break;
            case ElementType::quad:
                c.add_quads(elements<4>(cmd.values));
                break;
            case ElementType::tetrahedron:
                c.add_tetrahedra(elements<4>(cmd.values));
                break;
            case ElementType::hexahedron:
                c.add_hexahedra(elements<8>(cmd.values));
                break;
            case ElementType::point:
                break;
        }
    }
}

// TopologicalChangeProcessor::processTopologicalChanges(double) with useDataInputs: at each step
// past timeToRemove, each list (hexahedra first, points last) through the modifier of its class,
// then timeToRemove += interval (or never again).
void TopologicalChangeProcessorSource::remove_data_inputs(double time) {
    if (time_to_remove_ >= time) return;
    TopologyContainer& c = *target_->container;
    // every list checked first, against the count the earlier ones leave (each removes elements of
    // the container's level: SOFA calls the modifier's virtual removeItems), then all applied
    std::vector<std::vector<ElementId>> removals;
    std::size_t count = c.count(c.level());
    for (auto& list : lists_) {
        std::vector<ElementId> items = list.source ? list.source() : list.values;
        if (items.empty()) continue;
        if (!c.keeps(list.type) || c.level() < list.type)
            fail(list.line, std::string("no modifier of ") + element_type_name(list.type) + " in the topology '" +
                                target_->path + "'");
        try {
            runtime_->check_can_change(*target_);
            std::vector<char> seen(count, 0);
            for (const ElementId i : items) {
                if (i < 0 || std::size_t(i) >= count)
                    throw_invalid_argument(element_type_name(c.level()), " ", i, " does not exist (the topology '",
                                           target_->path, "' has ", count, ")");
                if (seen[std::size_t(i)])
                    throw_invalid_argument(element_type_name(c.level()), " ", i, " is listed twice");
                seen[std::size_t(i)] = 1;
            }
            count -= items.size();
            TopologyRuntime::check_keeps_elements(*target_, c.level(), count);
        } catch (const std::invalid_argument& e) {
            fail(list.line, e.what());
        }
        removals.push_back(std::move(items));
    }
    for (auto& items : removals) c.remove_items(std::move(items));
    time_to_remove_ = interval_ != 0.0 ? time_to_remove_ + interval_ : double(std::uint32_t(-1));
}

}  // namespace penalty::scene
