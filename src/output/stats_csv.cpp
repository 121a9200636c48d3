#include "penalty/output/stats_csv.hpp"

#include "output/file_io.hpp"
#include "penalty/core/error.hpp"
#include "penalty/output/format.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penalty::output {

const char* stats_csv_header() {
    return "step,time,contacts,active_contacts,max_penetration,contact_energy,kinetic_energy,dissipated_energy,"
           "detection_seconds,response_seconds,solve_seconds,output_seconds,cg_iterations,newton_iterations";
}

std::string stats_csv_header(bool tunnelling_columns) {
    std::string h = stats_csv_header();
    if (tunnelling_columns)
        h += ",crossings,crossings_prevented,first_crossing,max_crossing_depth,solves,stiffened_contacts,"
             "stiffening_energy,guard_seconds";
    return h;
}

namespace {

/// A CSV field: quoted (quotes doubled) when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

void append_tunnelling(std::string& row, const StepStats& stats) {
    const StepStats::Tunnelling& t = stats.tunnelling;
    for (const auto& [column, value] : {std::pair<const char*, double>{"max_crossing_depth", t.max_depth},
                                        {"stiffening_energy", t.stiffening_energy},
                                        {"guard_seconds", t.guard_seconds}})
        if (!std::isfinite(value))
            throw NonFiniteValueError(std::string("stats: ") + column + " is " + format_number(value) + " at step " +
                                      std::to_string(stats.step) + " (the simulation diverged)");
    row +=
        ',' + std::to_string(t.crossings) + ',' + std::to_string(t.prevented) + ',' + csv_field(t.first_crossing) + ',';
    append_number(row, t.max_depth);
    row += ',' + std::to_string(t.solves) + ',' + std::to_string(t.stiffened_contacts) + ',';
    append_number(row, t.stiffening_energy);
    row += ',';
    append_number(row, t.guard_seconds);
}

}  // namespace

std::string format_stats_row(const StepStats& stats, bool tunnelling_columns) {
    const std::pair<const char*, double> reals[] = {
        {"time", stats.time},
        {"max_penetration", stats.max_penetration},
        {"contact_energy", stats.contact_energy},
        {"kinetic_energy", stats.kinetic_energy},
        {"dissipated_energy", stats.dissipated_energy},
        {"detection_seconds", stats.detection_seconds},
        {"response_seconds", stats.response_seconds},
        {"solve_seconds", stats.solve_seconds},
        {"output_seconds", stats.output_seconds},
    };
    for (const auto& [column, value] : reals)
        if (!std::isfinite(value))
            throw NonFiniteValueError(std::string("stats: ") + column + " is " + format_number(value) + " at step " +
                                      std::to_string(stats.step) + " (the simulation diverged)");
    std::string row = std::to_string(stats.step);
    row += ',';
    append_number(row, stats.time);
    row += ',' + std::to_string(stats.contacts) + ',' + std::to_string(stats.active_contacts);
    for (std::size_t i = 1; i < std::size(reals); ++i) {
        row += ',';
        append_number(row, reals[i].second);
    }
    row += ',' + std::to_string(stats.cg_iterations) + ',' + std::to_string(stats.newton_iterations);
    if (tunnelling_columns) append_tunnelling(row, stats);
    return row;
}

StatsCsvWriter::StatsCsvWriter(const std::filesystem::path& file, bool tunnelling_columns)
    : file_(file), tunnelling_columns_(tunnelling_columns) {
    if (file_.has_parent_path()) detail::create_directory(file_.parent_path());
    stream_ = detail::open_output_file(file_);
    *stream_ << stats_csv_header(tunnelling_columns_) << '\n';
    stream_->flush();
    if (!*stream_) throw std::runtime_error("cannot write " + detail::quoted(file_));
}

void StatsCsvWriter::write(const StepStats& stats) {
    const std::string row = format_stats_row(stats, tunnelling_columns_);
    *stream_ << row << '\n';
    stream_->flush();
    if (!*stream_) throw std::runtime_error("cannot write " + detail::quoted(file_));
}

ContactSummary summarize_contacts(std::span<const ContactRecord> contacts) {
    ContactSummary summary;
    for (std::size_t p = 0; p < contacts.size(); ++p) {
        const ContactRecord& record = contacts[p];
        if (record.field == nullptr || record.state1 == nullptr || record.state2 == nullptr)
            throw_invalid_argument("summarize_contacts: contact record ", p, " ('", record.name,
                                   "') has a null field or state");
        summary.contacts += record.field->size();
        summary.active_contacts += record.field->active_count();
        summary.contact_energy += record.field->potential_energy();
        summary.dissipated_energy += record.field->dissipated_energy();
        // pen = dist − (x2 − x1)·n at the current positions (as export_contacts, without its copy)
        const auto& x1 = record.state1->position;
        const auto& x2 = record.state2->position;
        for (const PenaltyContact& c : record.field->contacts()) {
            if (std::size_t(c.m1) >= x1.size() || std::size_t(c.m2) >= x2.size())
                throw_invalid_argument("summarize_contacts: contact record ", p, " ('", record.name,
                                       "') refers to a DOF outside its states");
            summary.max_penetration = std::max(summary.max_penetration,
                                               c.dist - (x2[std::size_t(c.m2)] - x1[std::size_t(c.m1)]).dot(c.normal));
        }
    }
    return summary;
}

double kinetic_energy(std::span<const StateRecord> states) {
    double energy = 0.0;
    for (const StateRecord& record : states)
        if (record.mass != nullptr) energy += record.mass->kinetic_energy();
    return energy;
}

}  // namespace penalty::output
