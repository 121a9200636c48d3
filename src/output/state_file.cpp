#include "penalty/output/state_file.hpp"

#include "output/file_io.hpp"
#include "penalty/core/error.hpp"
#include "penalty/output/format.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace penalty::output {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The scalars of the X line of one DOF: x y z, or x y z qx qy qz qw.
template <class Visit>
void for_each_position_value(const BaseState& state, Visit&& visit) {
    if (const auto* vec3 = dynamic_cast<const Vec3Object*>(&state)) {
        for (std::size_t i = 0; i < vec3->position.size(); ++i)
            for (int c = 0; c < 3; ++c) visit(i, vec3->position[i][c]);
    } else if (const auto* rigid = dynamic_cast<const Rigid3Object*>(&state)) {
        for (std::size_t i = 0; i < rigid->position.size(); ++i) {
            const RigidFrame& frame = rigid->position[i];
            for (int c = 0; c < 3; ++c) visit(i, frame.center[c]);
            const Quat& q = frame.orientation;
            visit(i, q.x());
            visit(i, q.y());
            visit(i, q.z());
            visit(i, q.w());
        }
    } else {
        throw_invalid_argument("state '", state.state_name(), "' is neither Vec3d nor Rigid3d");
    }
}

void check_finite_positions(const StateRecord& record, double time) {
    for_each_position_value(*record.state, [&](std::size_t dof, double value) {
        if (!std::isfinite(value))
            throw NonFiniteValueError("state " + state_label(record) + ": position of DOF " + std::to_string(dof) +
                                      " is " + format_number(value) + " at time " + format_number(time) +
                                      " (the simulation diverged)");
    });
}

std::string_view trim_left(std::string_view s) {
    const auto first = s.find_first_not_of(" \t\r");
    return first == std::string_view::npos ? std::string_view{} : s.substr(first);
}

std::vector<std::string_view> split_words(std::string_view s) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
        if (i > start) words.push_back(s.substr(start, i - start));
    }
    return words;
}

[[noreturn]] void fail_at(const std::filesystem::path& file, std::size_t line, const std::string& reason) {
    throw std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + reason);
}

double parse_number(std::string_view word, const std::filesystem::path& file, std::size_t line) {
    double value = 0.0;
    const char* begin = word.data();
    const char* end = word.data() + word.size();
    if (!word.empty() && *begin == '+') ++begin;  // from_chars rejects a leading '+', ostream never writes one
    const auto result = std::from_chars(begin, end, value);
    if (result.ec != std::errc{} || result.ptr != end)
        fail_at(file, line, "'" + std::string(word) + "' is not a number");
    return value;
}

}  // namespace

// --- StateExporter ------------------------------------------------------------------------------

StateExporter::StateExporter(std::filesystem::path directory, std::vector<const StateRecord*> states)
    : states_(std::move(states)) {
    for (std::size_t k = 0; k < states_.size(); ++k) {
        if (states_[k] == nullptr || states_[k]->state == nullptr)
            throw_invalid_argument("StateExporter: state record ", k, " has no state");
        values_per_dof_.push_back(output::values_per_dof(*states_[k]->state));
    }
    detail::create_directory(directory);
    for (std::size_t k = 0; k < states_.size(); ++k) {
        files_.push_back(directory / (std::to_string(k) + "_" + sanitize_file_name(states_[k]->name) + "_mstate.txt"));
        auto stream = std::make_unique<std::ofstream>(files_.back(), std::ios::binary | std::ios::trunc);
        if (!*stream) throw std::runtime_error("cannot open " + detail::quoted(files_.back()) + " for writing");
        streams_.push_back(std::move(stream));
    }
}

StateExporter::~StateExporter() = default;
StateExporter::StateExporter(StateExporter&&) noexcept = default;
StateExporter& StateExporter::operator=(StateExporter&&) noexcept = default;

void StateExporter::write(double time) {
    if (!std::isfinite(time)) throw NonFiniteValueError("StateExporter: time is " + format_number(time));
    for (const StateRecord* record : states_) check_finite_positions(*record, time);
    std::string header = "T= ";
    append_number(header, time);
    header += "\n  X= ";
    for (std::size_t k = 0; k < states_.size(); ++k) {
        std::ofstream& out = *streams_[k];
        out << header << format_positions(*states_[k]->state) << '\n';
        out.flush();
        if (!out) throw std::runtime_error("cannot write " + detail::quoted(files_[k]));
    }
}

std::string format_positions(const BaseState& state) {
    std::string line;
    bool first = true;
    for_each_position_value(state, [&](std::size_t, double value) {
        if (!first) line += ' ';
        first = false;
        append_number(line, value);
    });
    return line;
}

// --- reader -------------------------------------------------------------------------------------

std::vector<StateSample> read_state_file(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open state file " + detail::quoted(file));
    std::vector<StateSample> samples;
    bool has_x = true;  // the current sample (if any) has its X line
    std::size_t sample_line = 0;
    std::string text;
    std::size_t line_number = 0;
    while (std::getline(in, text)) {
        ++line_number;
        const std::string_view line = trim_left(text);
        const std::vector<std::string_view> words = split_words(line);
        if (words.empty()) continue;
        const std::string_view keyword = words.front();
        if (keyword == "T=") {
            if (!has_x) fail_at(file, sample_line, "sample T= " + format_number(samples.back().time) + " has no X line");
            if (words.size() != 2) fail_at(file, line_number, "expected 'T= <time>'");
            samples.push_back({parse_number(words[1], file, line_number), {}});
            has_x = false;
            sample_line = line_number;
        } else if (keyword == "X=") {
            if (samples.empty()) fail_at(file, line_number, "X line before any T line");
            if (has_x) fail_at(file, line_number, "second X line for T= " + format_number(samples.back().time));
            std::vector<double>& x = samples.back().x;
            x.reserve(words.size() - 1);
            for (std::size_t w = 1; w < words.size(); ++w) x.push_back(parse_number(words[w], file, line_number));
            has_x = true;
        } else if (keyword == "V=") {
            if (samples.empty()) fail_at(file, line_number, "V line before any T line");
        } else {
            fail_at(file, line_number, "unknown keyword '" + std::string(keyword) + "' (expected T=, X= or V=)");
        }
    }
    if (in.bad()) throw std::runtime_error("cannot read state file " + detail::quoted(file));
    if (!has_x) fail_at(file, sample_line, "sample T= " + format_number(samples.back().time) + " has no X line");
    return samples;
}

// --- regression ---------------------------------------------------------------------------------

double state_regression_error(std::span<const StateSample> reference, std::span<const StateSample> ours,
                              int values_per_dof, const std::string& label, std::vector<std::string>& messages) {
    if (values_per_dof <= 0) throw_invalid_argument("state_regression_error: values_per_dof = ", values_per_dof);
    const auto fail = [&](const std::string& message) {
        messages.push_back(label + ": " + message);
        return kInfinity;
    };
    if (reference.empty()) return fail("the reference has no sample");
    const std::size_t width = reference.front().x.size();
    if (width % static_cast<std::size_t>(values_per_dof) != 0)
        return fail("reference X line at T= " + format_number(reference.front().time) + " has " +
                    std::to_string(width) + " values, not a multiple of " + std::to_string(values_per_dof) +
                    " values per DOF");
    const std::size_t num_dofs = width / static_cast<std::size_t>(values_per_dof);

    double sum = 0.0;  // Σ_T Σ_i |X_i(T) − Xref_i(T)|
    for (const StateSample& expected : reference) {
        // SOFA writes times with 6 significant digits: a reference time matches our closest
        // sample within half a unit of its 6th digit (and within 1e-9·max(1, |T|) at least).
        const double magnitude = std::abs(expected.time);
        const double rounding = magnitude > 0 ? 0.5 * std::pow(10.0, std::floor(std::log10(magnitude)) - 5.0) : 0.0;
        const double tolerance = std::max(1e-9 * std::max(1.0, magnitude), rounding);
        auto match = ours.end();
        for (auto it = ours.begin(); it != ours.end(); ++it) {
            const double gap = std::abs(it->time - expected.time);
            if (gap <= tolerance && (match == ours.end() || gap < std::abs(match->time - expected.time))) match = it;
        }
        if (match == ours.end()) return fail("no sample at reference time T= " + format_number(expected.time));
        if (match->x.size() != expected.x.size())
            return fail("at T= " + format_number(expected.time) + " X has " + std::to_string(match->x.size()) +
                        " values, the reference has " + std::to_string(expected.x.size()));
        for (std::size_t i = 0; i < expected.x.size(); ++i) {
            if (!std::isfinite(match->x[i]) || !std::isfinite(expected.x[i]))
                return fail("non-finite value " + std::to_string(i) + " at T= " + format_number(expected.time) +
                            " (ours " + format_number(match->x[i]) + ", reference " + format_number(expected.x[i]) +
                            ")");
            sum += std::abs(match->x[i] - expected.x[i]);
        }
    }
    return num_dofs == 0 ? 0.0 : sum / static_cast<double>(num_dofs);
}

RegressionResult compare_with_reference(std::span<const std::filesystem::path> reference_files,
                                        std::span<const std::filesystem::path> our_files,
                                        std::span<const int> values_per_dof) {
    if (values_per_dof.size() != reference_files.size())
        throw_invalid_argument("compare_with_reference: ", values_per_dof.size(), " values_per_dof for ",
                               reference_files.size(), " reference files");
    RegressionResult result;
    const std::size_t common = std::min(reference_files.size(), our_files.size());
    if (reference_files.size() != our_files.size())
        result.messages.push_back(std::to_string(reference_files.size()) + " reference files but " +
                                  std::to_string(our_files.size()) + " files of ours");
    for (std::size_t s = 0; s < common; ++s) {
        const std::string label = our_files[s].string() + " (reference " + reference_files[s].string() + ")";
        std::vector<StateSample> reference;
        std::vector<StateSample> ours;
        try {
            reference = read_state_file(reference_files[s]);
            ours = read_state_file(our_files[s]);
        } catch (const std::runtime_error& error) {
            result.messages.push_back(error.what());
            result.per_state_error.push_back(kInfinity);
            continue;
        }
        result.per_state_error.push_back(
            state_regression_error(reference, ours, values_per_dof[s], label, result.messages));
    }
    double total = 0.0;
    for (double error : result.per_state_error) total += error;
    result.mean_error = result.per_state_error.empty() ? 0.0 : total / static_cast<double>(result.per_state_error.size());
    if (reference_files.size() != our_files.size()) result.mean_error = kInfinity;
    return result;
}

}  // namespace penalty::output
