#pragma once
/// @file
/// The contacts of a ContactPipeline as the writers see them (vtk_writer.hpp, stats_csv.hpp).

#include "penalty/output/vtk_writer.hpp"
#include "penalty/simulation/contact_pipeline.hpp"

#include <vector>

namespace penalty::output {

/// The record of one live pair (a graph entry with its contact and point states): see
/// contact_records.
[[nodiscard]] ContactRecord contact_record(const ContactGraphEntry& entry);
/// Whether `record` is `entry`'s: the same field, point states and name (a new pair's objects may
/// have a destroyed pair's addresses; the name tells their models apart). Makes no string.
[[nodiscard]] bool is_record_of(const ContactRecord& record, const ContactGraphEntry& entry);

/// One ContactRecord per live pair of `pipeline`, in graph_entries() order: name
/// "<model1 name>-<model2 name>" (collision model names), field = the pair's PenaltyForceField,
/// state1 / state2 = the contact-point states the field acts on (ContactGraphEntry::point_states).
/// The records point into the pipeline: rebuild them after every ContactPipeline::update().
[[nodiscard]] std::vector<ContactRecord> contact_records(const ContactPipeline& pipeline);

}  // namespace penalty::output
