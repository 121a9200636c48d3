#include "penalty/output/viewer_writer.hpp"

#include "output/output_folder.hpp"
#include "penalty/core/error.hpp"
#include "penalty/output/format.hpp"
#include "penalty/output/stats_csv.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <type_traits>

namespace penalty::output {

static_assert(std::endian::native == std::endian::little, "the viewer's binary files are little-endian");

const char* viewer_shape_kind_name(ViewerShapeKind kind) {
    switch (kind) {
        case ViewerShapeKind::triangles:
            return "triangles";
        case ViewerShapeKind::lines:
            return "lines";
        case ViewerShapeKind::points:
            return "points";
        case ViewerShapeKind::spheres:
            return "spheres";
        case ViewerShapeKind::cylinders:
            return "cylinders";
    }
    return "points";
}

namespace {

/// JSON string literal of `text` (quotes, backslashes and control characters escaped).
void append_json_string(std::string& out, std::string_view text) {
    out += '"';
    for (const char c : text) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    out += '"';
}

template <class T, class F>
void append_json_array(std::string& out, const std::vector<T>& items, F&& each) {
    out += '[';
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += ',';
        each(items[i]);
    }
    out += ']';
}

void write_floats(detail::CreatedFile& out, const std::vector<float>& data) {
    out.write(data.data(), data.size() * sizeof(float));
}

bool finite(const Vec3& v) { return v.allFinite(); }

void write_page(const detail::OutputFolder& folder) {
    for (const ViewerAsset& asset : viewer_assets()) folder.replace_file(asset.name, asset.content);
}

}  // namespace

void write_viewer_page(const std::filesystem::path& directory) { write_page(detail::OutputFolder(directory)); }

ViewerWriter::ViewerWriter(std::filesystem::path directory, std::vector<const StateRecord*> states,
                           std::vector<ViewerShape> shapes, std::string title)
    : directory_(std::move(directory)), states_(std::move(states)), title_(std::move(title)) {
    std::vector<std::size_t> dofs;
    for (std::size_t k = 0; k < states_.size(); ++k) {
        const StateRecord* r = states_[k];
        if (r == nullptr || r->state == nullptr)
            throw std::invalid_argument("ViewerWriter: state " + std::to_string(k) + " is null");
        frame_floats_ += r->state->num_dofs() * std::size_t(values_per_dof(*r->state));  // throws if unsupported
        dofs.push_back(r->state->num_dofs());
    }
    std::string indices;
    Layout layout = make_layout(std::move(shapes), std::move(dofs), 0, indices);  // checked before anything is written
    folder_ = std::make_unique<detail::OutputFolder>(directory_);
    // A stale manifest of an earlier run in DIR would describe other files.
    folder_->remove("run.json");
    folder_->remove("crossings.f32");  // written only when this run has a crossing
    write_page(*folder_);
    topology_ = std::make_unique<detail::CreatedFile>(folder_->create_file("topology.u32"));
    append_layout(std::move(layout), indices);
    positions_ = std::make_unique<detail::CreatedFile>(folder_->create_file("positions.f32"));
    contacts_ = std::make_unique<detail::CreatedFile>(folder_->create_file("contacts.f32"));
}

void ViewerWriter::follow_topology(std::function<std::uint64_t()> revision,
                                   std::function<std::vector<ViewerShape>()> shapes) {
    revision_ = std::move(revision);
    reshape_ = std::move(shapes);
    if (revision_) layouts_.back().revision = revision_();
}

ViewerWriter::Layout ViewerWriter::make_layout(std::vector<ViewerShape> shapes, std::vector<std::size_t> dofs,
                                               std::uint64_t revision, std::string& topology) const {
    Layout layout;
    for (std::size_t k = 0; k < states_.size(); ++k) {
        layout.state_offsets.push_back(layout.floats);
        layout.floats += dofs[k] * std::size_t(values_per_dof(*states_[k]->state));
    }
    layout.dofs = std::move(dofs);
    layout.revision = revision;
    for (std::size_t s = 0; s < shapes.size(); ++s) {
        const ViewerShape& shape = shapes[s];
        const std::string what = "ViewerWriter: shape '" + shape.name + "'";
        if (shape.state >= states_.size())
            throw std::invalid_argument(what + ": state index " + std::to_string(shape.state) + " out of range (" +
                                        std::to_string(states_.size()) + " states)");
        for (const std::uint32_t i : shape.indices)
            if (i >= layout.dofs[shape.state])
                throw std::invalid_argument(what + ": DOF index " + std::to_string(i) + " out of range (state '" +
                                            state_label(*states_[shape.state]) + "' has " +
                                            std::to_string(layout.dofs[shape.state]) + " DOFs)");
        const std::size_t per = shape.kind == ViewerShapeKind::triangles ? 3
                                : shape.kind == ViewerShapeKind::lines   ? 2
                                                                         : 1;
        if (shape.indices.size() % per != 0)
            throw std::invalid_argument(what + ": " + std::to_string(shape.indices.size()) +
                                        " indices, not a multiple of " + std::to_string(per));
        const std::size_t elements = shape.indices.size() / per;
        const bool rigid_only = shape.kind == ViewerShapeKind::cylinders;
        if (rigid_only && values_per_dof(*states_[shape.state]->state) != 7)
            throw std::invalid_argument(what + ": cylinders need a Rigid3 state");
        if ((shape.kind == ViewerShapeKind::spheres || rigid_only) && shape.radius.size() != elements)
            throw std::invalid_argument(what + ": " + std::to_string(shape.radius.size()) + " radii for " +
                                        std::to_string(elements) + " elements");
        if (rigid_only && (shape.height.size() != elements || shape.axis.size() != elements))
            throw std::invalid_argument(what + ": cylinders need one height and one axis per element");
        layout.index_offsets.push_back(topology_size_ + topology.size() / sizeof(std::uint32_t));
        layout.index_counts.push_back(shape.indices.size());
        topology.append(reinterpret_cast<const char*>(shape.indices.data()),
                        shape.indices.size() * sizeof(std::uint32_t));
    }
    for (ViewerShape& shape : shapes) shape.indices = {};  // kept in `topology`
    layout.shapes = std::move(shapes);
    return layout;
}

void ViewerWriter::append_layout(Layout layout, const std::string& topology) {
    topology_->write(topology.data(), topology.size());
    topology_size_ += topology.size() / sizeof(std::uint32_t);
    layouts_.push_back(std::move(layout));
}

ViewerWriter::~ViewerWriter() {
    if (finished_) return;
    try {
        finish();
    } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw; the run's error is reported
    }
}

void ViewerWriter::write_frame(double time, std::span<const ContactRecord> contacts, double kinetic_energy,
                               std::span<const Vec3> crossings) {
    // Positions: check every value first, so that nothing of a diverged frame is written.
    buffer_.clear();
    buffer_.reserve(frame_floats_);
    for (const StateRecord* r : states_) {
        auto fail = [&](std::size_t dof) {
            throw NonFiniteValueError("viewer: state '" + state_label(*r) + "' DOF " + std::to_string(dof) +
                                      " is not finite at t = " + format_number(time) + " s: the simulation diverged");
        };
        if (const auto* v = dynamic_cast<const Vec3Object*>(r->state)) {
            for (std::size_t i = 0; i < v->position.size(); ++i) {
                const Vec3& p = v->position[i];
                if (!finite(p)) fail(i);
                buffer_.insert(buffer_.end(), {float(p.x()), float(p.y()), float(p.z())});
            }
        } else if (const auto* g = dynamic_cast<const Rigid3Object*>(r->state)) {
            for (std::size_t i = 0; i < g->position.size(); ++i) {
                const Vec3& c = g->position[i].center;
                const Quat& q = g->position[i].orientation;
                if (!finite(c) || !q.coeffs().allFinite()) fail(i);
                buffer_.insert(buffer_.end(), {float(c.x()), float(c.y()), float(c.z()), float(q.x()), float(q.y()),
                                               float(q.z()), float(q.w())});
            }
        }
    }
    if (!std::isfinite(time)) throw NonFiniteValueError("viewer: the time is not finite: the simulation diverged");
    // a new layout when the elements or the states' sizes changed (topological changes)
    std::vector<std::size_t> dofs;
    for (const StateRecord* r : states_) dofs.push_back(r->state->num_dofs());
    const std::uint64_t revision = revision_ ? revision_() : 0;
    if (dofs != layouts_.back().dofs || revision != layouts_.back().revision) {
        if (!reshape_)
            throw std::invalid_argument("viewer: the states changed size during the run (" +
                                        std::to_string(buffer_.size()) + " position values, " +
                                        std::to_string(frame_floats_) + " at the start)");
        std::string indices;
        Layout layout = make_layout(reshape_(), std::move(dofs), revision, indices);
        append_layout(std::move(layout), indices);
    }

    std::vector<float> segments;
    double max_force = max_normal_force_;
    for (std::size_t p = 0; p < contacts.size(); ++p) {
        const ContactRecord& rec = contacts[p];
        if (rec.field == nullptr || rec.state1 == nullptr || rec.state2 == nullptr)
            throw std::invalid_argument("viewer: contact record " + std::to_string(p) + " has a null field or state");
        const std::vector<ContactSegment> list = rec.field->export_contacts(rec.state1->position, rec.state2->position);
        for (std::size_t c = 0; c < list.size(); ++c) {
            const ContactSegment& s = list[c];
            const double normal_force = s.force.dot(s.normal);  // N, on side 2 along n
            if (!finite(s.point1) || !finite(s.point2) || !finite(s.normal) || !std::isfinite(normal_force))
                throw NonFiniteValueError("viewer: contact " + std::to_string(c) + " of '" + rec.name +
                                          "' is not finite at t = " + format_number(time) +
                                          " s: the simulation diverged");
            segments.insert(segments.end(),
                            {float(s.point1.x()), float(s.point1.y()), float(s.point1.z()), float(s.point2.x()),
                             float(s.point2.y()), float(s.point2.z()), float(s.normal.x()), float(s.normal.y()),
                             float(s.normal.z()), float(normal_force)});
            max_force = std::max(max_force, std::abs(normal_force));
        }
    }
    const ContactSummary summary = summarize_contacts(contacts);
    FrameStats stats;
    stats.time = time;
    stats.contacts = segments.size() / kContactFloats;
    stats.active_contacts = summary.active_contacts;
    stats.max_penetration = summary.max_penetration;
    stats.contact_energy = summary.contact_energy;
    stats.kinetic_energy = kinetic_energy;
    stats.dissipated_energy = summary.dissipated_energy;
    if (!std::isfinite(stats.contact_energy) || !std::isfinite(stats.dissipated_energy) ||
        !std::isfinite(stats.max_penetration))
        throw NonFiniteValueError("viewer: contact energy not finite at t = " + format_number(time) +
                                  " s: the simulation diverged");

    std::vector<float> markers;
    for (const Vec3& x : crossings)
        if (x.allFinite()) markers.insert(markers.end(), {float(x.x()), float(x.y()), float(x.z())});
    stats.crossings = markers.size() / 3;

    write_floats(*positions_, buffer_);
    write_floats(*contacts_, segments);
    if (!markers.empty()) {
        if (!crossings_) crossings_ = std::make_unique<detail::CreatedFile>(folder_->create_file("crossings.f32"));
        write_floats(*crossings_, markers);
    }
    max_normal_force_ = max_force;
    stats.layout = layouts_.size() - 1;
    stats.position_offset = positions_size_;
    positions_size_ += buffer_.size();
    frames_.push_back(stats);
}

void ViewerWriter::finish() {
    std::string j;
    j.reserve(4096 + frames_.size() * 100);
    const bool layouts = layouts_.size() > 1;
    j += "{\"format\":\"penalty-viewer\",\"version\":";
    j += layouts ? "2" : "1";
    j += ",\"title\":";
    append_json_string(j, title_);
    j += ",\"frame_floats\":" + std::to_string(frame_floats_);
    j += ",\"contact_floats\":" + std::to_string(kContactFloats);
    j += ",\"max_normal_force\":";
    append_number(j, max_normal_force_);
    j += ",\"units\":{\"length\":\"m\",\"time\":\"s\",\"force\":\"N\",\"energy\":\"J\"}";
    // states and shapes of layout `l` (the top-level lists are layout 0's: version 1 readers)
    auto append_states = [&](const Layout& layout) {
        std::size_t k = 0;
        append_json_array(j, states_, [&](const StateRecord* r) {
            j += "{\"name\":";
            append_json_string(j, r->name);
            j += ",\"node_path\":";
            append_json_string(j, r->node_path);
            j += ",\"type\":";
            j += values_per_dof(*r->state) == 7 ? "\"Rigid3d\"" : "\"Vec3d\"";
            j += ",\"dofs\":" + std::to_string(layout.dofs[k]);
            j += ",\"offset\":" + std::to_string(layout.state_offsets[k]);
            j += ",\"mapped\":";
            j += r->mapped ? "true" : "false";
            j += '}';
            ++k;
        });
    };
    auto append_shapes = [&](const Layout& layout) {
        std::size_t s = 0;
        append_json_array(j, layout.shapes, [&](const ViewerShape& shape) {
            j += "{\"name\":";
            append_json_string(j, shape.name);
            j += ",\"type\":";
            append_json_string(j, shape.type);
            j += ",\"kind\":\"";
            j += viewer_shape_kind_name(shape.kind);
            j += "\",\"state\":" + std::to_string(shape.state);
            j += ",\"index_offset\":" + std::to_string(layout.index_offsets[s]);
            j += ",\"index_count\":" + std::to_string(layout.index_counts[s]);
            auto numbers = [&](const std::vector<double>& v) {
                append_json_array(j, v, [&](double x) { append_number(j, x); });
            };
            if (!shape.radius.empty()) {
                j += ",\"radius\":";
                numbers(shape.radius);
            }
            if (!shape.height.empty()) {
                j += ",\"height\":";
                numbers(shape.height);
            }
            if (!shape.axis.empty()) {
                j += ",\"axis\":";
                append_json_array(j, shape.axis, [&](const Vec3& a) {
                    j += '[';
                    append_number(j, a.x());
                    j += ',';
                    append_number(j, a.y());
                    j += ',';
                    append_number(j, a.z());
                    j += ']';
                });
            }
            j += '}';
            ++s;
        });
    };
    j += ",\"states\":";
    append_states(layouts_.front());
    j += ",\"shapes\":";
    append_shapes(layouts_.front());
    if (layouts) {
        j += ",\"layouts\":";
        append_json_array(j, layouts_, [&](const Layout& layout) {
            j += "{\"frame_floats\":" + std::to_string(layout.floats);
            j += ",\"states\":";
            append_states(layout);
            j += ",\"shapes\":";
            append_shapes(layout);
            j += '}';
        });
    }
    j += ",\"frames\":{\"count\":" + std::to_string(frames_.size());
    auto column = [&](const char* name, auto member) {
        j += ",\"";
        j += name;
        j += "\":";
        append_json_array(j, frames_, [&](const FrameStats& f) {
            if constexpr (std::is_same_v<std::decay_t<decltype(f.*member)>, std::size_t>)
                j += std::to_string(f.*member);
            else if (!std::isfinite(f.*member))
                j += "null";  // a kinetic energy that overflowed (v² beyond double) just before divergence
            else append_number(j, f.*member);
        });
    };
    column("time", &FrameStats::time);
    column("contacts", &FrameStats::contacts);
    column("active_contacts", &FrameStats::active_contacts);
    column("max_penetration", &FrameStats::max_penetration);
    column("contact_energy", &FrameStats::contact_energy);
    column("kinetic_energy", &FrameStats::kinetic_energy);
    column("dissipated_energy", &FrameStats::dissipated_energy);
    if (layouts) {
        column("layout", &FrameStats::layout);
        column("position_offset", &FrameStats::position_offset);
    }
    if (crossings_) column("crossings", &FrameStats::crossings);
    j += "}}\n";
    // Written beside, then renamed: a server reading run.json never sees half a file.
    folder_->replace_file("run.json", j);
    finished_ = true;
}

}  // namespace penalty::output
