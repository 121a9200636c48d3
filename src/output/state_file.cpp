#include "penalty/output/state_file.hpp"

#include "output/file_io.hpp"

#include <fstream>
#include "penalty/core/error.hpp"
#include "penalty/output/format.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <zlib.h>

namespace penalty::output {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The scalars of the X line of one DOF: x y z, x y z qx qy qz qw, or the one value of a Vec1d.
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
    } else if (const auto* vec1 = dynamic_cast<const Vec1Object*>(&state)) {
        for (std::size_t i = 0; i < vec1->position.size(); ++i) visit(i, vec1->position[i]);
    } else {
        throw_invalid_argument("state '", state.state_name(), "' is neither Vec3d, Rigid3d nor Vec1d");
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

StateExporter::StateExporter(const std::filesystem::path& directory, std::vector<const StateRecord*> states)
    : states_(std::move(states)) {
    for (std::size_t k = 0; k < states_.size(); ++k) {
        if (states_[k] == nullptr || states_[k]->state == nullptr)
            throw_invalid_argument("StateExporter: state record ", k, " has no state");
        values_per_dof_.push_back(output::values_per_dof(*states_[k]->state));
    }
    detail::create_directory(directory);
    for (std::size_t k = 0; k < states_.size(); ++k) {
        files_.push_back(directory / (std::to_string(k) + "_" + sanitize_file_name(states_[k]->name) + "_mstate.txt"));
        streams_.push_back(detail::open_output_file(files_.back()));
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
        std::ostream& out = *streams_[k];
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

namespace {
/// The whole content of a file, decompressed when its name ends in ".gz" (SOFA's compressed
/// trajectories and references). Throws std::runtime_error naming the file.
std::string read_possibly_compressed(const std::filesystem::path& file) {
    std::string content;
    if (file.extension() == ".gz") {
        gzFile in = gzopen(file.c_str(), "rb");
        if (in == nullptr) throw std::runtime_error("cannot open state file " + detail::quoted(file));
        char buffer[1 << 16];
        int n = 0;
        while ((n = gzread(in, buffer, sizeof buffer)) > 0) content.append(buffer, std::size_t(n));
        const bool failed = n < 0;
        gzclose(in);
        if (failed) throw std::runtime_error("cannot decompress state file " + detail::quoted(file));
        return content;
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open state file " + detail::quoted(file));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw std::runtime_error("cannot read state file " + detail::quoted(file));
    return std::move(text).str();
}
}  // namespace

std::vector<StateSample> read_state_file(const std::filesystem::path& file) {
    std::istringstream in(read_possibly_compressed(file));
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
            if (!has_x)
                fail_at(file, sample_line, "sample T= " + format_number(samples.back().time) + " has no X line");
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
    result.mean_error =
        result.per_state_error.empty() ? 0.0 : total / static_cast<double>(result.per_state_error.size());
    if (reference_files.size() != our_files.size()) result.mean_error = kInfinity;
    return result;
}

// --- trajectory comparison ----------------------------------------------------------------------

namespace {
/// "<k>" of a state file name "<k>_<name>_mstate.txt[.gz]", or nullopt.
std::optional<std::size_t> state_file_index(const std::string& name) {
    std::size_t k = 0;
    const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), k);
    if (ec != std::errc{} || end == name.data() || end == name.data() + name.size() || *end != '_') return std::nullopt;
    return k;
}
std::string state_file_stem(std::string name) {
    if (name.size() > 3 && name.ends_with(".gz")) name.resize(name.size() - 3);
    return name;
}
}  // namespace

std::vector<std::filesystem::path> find_trajectory_files(const std::filesystem::path& directory,
                                                         std::span<const std::filesystem::path> our_files,
                                                         std::vector<std::string>& messages) {
    std::error_code ec;
    if (!std::filesystem::is_directory(directory, ec))
        throw std::runtime_error("trajectory directory " + detail::quoted(directory) + " does not exist");
    std::map<std::size_t, std::vector<std::filesystem::path>> by_index;
    for (const auto& entry : std::filesystem::directory_iterator(directory)) {
        const std::string name = entry.path().filename().string();
        const std::string stem = state_file_stem(name);
        if (!stem.ends_with("_mstate.txt")) continue;
        if (const auto k = state_file_index(name)) by_index[*k].push_back(entry.path());
    }
    std::vector<std::filesystem::path> out;
    for (std::size_t k = 0; k < our_files.size(); ++k) {
        const std::string ours = our_files[k].filename().string();
        const auto it = by_index.find(k);
        if (it == by_index.end()) {
            messages.push_back("no SOFA state file " + std::to_string(k) + "_*_mstate.txt[.gz] in " +
                               detail::quoted(directory) + " for " + ours);
            out.emplace_back();
            continue;
        }
        // Same index: the file whose name matches ours (SOFA's names may hold spaces, which our
        // file names replace by '_'), else the only one with that index.
        std::filesystem::path chosen;
        for (const auto& f : it->second)
            if (sanitize_file_name(state_file_stem(f.filename().string())) == ours) chosen = f;
        if (chosen.empty()) {
            chosen = it->second.front();
            messages.push_back("note: SOFA's state file " + chosen.filename().string() + " is compared with " + ours +
                               " (same index, different name)");
        }
        out.push_back(chosen);
    }
    if (!by_index.empty() && by_index.rbegin()->first >= our_files.size())
        messages.push_back(std::to_string(by_index.rbegin()->first + 1 - our_files.size()) +
                           " more SOFA state file index(es) in " + detail::quoted(directory) +
                           " than exported states (" + std::to_string(our_files.size()) + ")");
    return out;
}

TrajectoryStateComparison compare_state_trajectory(std::span<const StateSample> sofa, std::span<const StateSample> ours,
                                                   int values_per_dof, double threshold) {
    if (values_per_dof <= 0) throw_invalid_argument("compare_state_trajectory: values_per_dof = ", values_per_dof);
    TrajectoryStateComparison c;
    const auto vpd = static_cast<std::size_t>(values_per_dof);
    double sum = 0.0;   // SOFA's error_s over the compared samples: Σ_T Σ_i |ΔX_i(T)| / n_dofs
    std::size_t j = 0;  // both files are in time order: walk ours alongside SOFA's
    for (std::size_t step = 0; step < sofa.size(); ++step) {
        const StateSample& expected = sofa[step];
        const double tolerance = 1e-9 * std::max(1.0, std::abs(expected.time));
        while (j < ours.size() && ours[j].time < expected.time - tolerance) ++j;
        if (j == ours.size() || std::abs(ours[j].time - expected.time) > tolerance) {  // not exported
            ++c.sofa_steps_not_compared;
            continue;
        }
        const StateSample& mine = ours[j];
        if (mine.x.size() != expected.x.size()) {
            c.problem = "at step " + std::to_string(step) + " (T= " + format_number(expected.time) + ") X has " +
                        std::to_string(mine.x.size()) + " values, SOFA's " + std::to_string(expected.x.size());
            c.criterion = kInfinity;
            return c;
        }
        ++c.steps_compared;
        StepDifference d{step, expected.time, 0, 0.0};
        for (std::size_t i = 0; i < expected.x.size(); ++i) {
            const double diff = std::abs(mine.x[i] - expected.x[i]);
            sum += diff;
            if (diff > d.max_difference || std::isnan(diff)) {
                d.max_difference = std::isnan(diff) ? kInfinity : diff;
                d.value_index = i;
            }
        }
        d.dof = d.value_index / vpd;
        d.component = d.value_index % vpd;
        if (!c.first_over_threshold && d.max_difference > threshold) c.first_over_threshold = d;
        if (!c.largest || d.max_difference > c.largest->max_difference) c.largest = d;
        c.last = d;
    }
    const std::size_t dofs = sofa.empty() ? 0 : sofa.front().x.size() / vpd;
    c.criterion = dofs == 0 ? 0.0 : sum / static_cast<double>(dofs);
    if (std::isnan(c.criterion)) c.criterion = kInfinity;
    if (c.steps_compared == 0) c.problem = "no exported time matches a time of SOFA's file";
    return c;
}

bool TrajectoryComparison::passed(double criterion_tolerance) const {
    if (!messages_are_notes() || !(mean_criterion <= criterion_tolerance)) return false;
    for (const TrajectoryStateComparison& s : states)
        if (s.first_over_threshold || !s.problem.empty() || s.steps_compared == 0) return false;
    return true;
}

bool TrajectoryComparison::messages_are_notes() const {
    return std::all_of(messages.begin(), messages.end(), [](const std::string& m) { return m.starts_with("note: "); });
}

TrajectoryComparison compare_trajectories(const std::filesystem::path& sofa_directory,
                                          std::span<const std::filesystem::path> our_files,
                                          std::span<const int> values_per_dof, double threshold) {
    if (values_per_dof.size() != our_files.size())
        throw_invalid_argument("compare_trajectories: ", values_per_dof.size(), " values_per_dof for ",
                               our_files.size(), " files");
    if (!(threshold >= 0.0)) throw_invalid_argument("compare_trajectories: threshold ", threshold, " must be >= 0");
    TrajectoryComparison result;
    result.threshold = threshold;
    const std::vector<std::filesystem::path> sofa_files =
        find_trajectory_files(sofa_directory, our_files, result.messages);
    double total = 0.0;
    for (std::size_t k = 0; k < our_files.size(); ++k) {
        TrajectoryStateComparison c;
        c.sofa_file = sofa_files[k];
        c.our_file = our_files[k];
        if (c.sofa_file.empty()) {
            c.criterion = kInfinity;
            c.problem = "no SOFA file";
        } else {
            try {
                const std::vector<StateSample> sofa = read_state_file(c.sofa_file);
                const std::vector<StateSample> ours = read_state_file(c.our_file);
                TrajectoryStateComparison computed = compare_state_trajectory(sofa, ours, values_per_dof[k], threshold);
                computed.sofa_file = c.sofa_file;
                computed.our_file = c.our_file;
                c = std::move(computed);
            } catch (const std::runtime_error& error) {
                c.criterion = kInfinity;
                c.problem = error.what();
            }
        }
        total += c.criterion;
        result.states.push_back(std::move(c));
    }
    result.mean_criterion = result.states.empty() ? 0.0 : total / static_cast<double>(result.states.size());
    return result;
}

namespace {
std::string describe_difference(const StepDifference& d) {
    static constexpr const char* kComponents[] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
    return "step " + std::to_string(d.step) + " (t = " + format_number(d.time) + " s) DOF " + std::to_string(d.dof) +
           " " + (d.component < 7 ? kComponents[d.component] : "?") + ": " + format_number(d.max_difference);
}
}  // namespace

std::string format_trajectory_comparison(const TrajectoryComparison& c) {
    std::ostringstream out;
    for (const std::string& m : c.messages) out << "trajectory: " << m << "\n";
    bool all_within = true;
    for (const TrajectoryStateComparison& s : c.states) {
        out << "trajectory: " << s.our_file.filename().string();
        if (!s.sofa_file.empty()) out << " vs " << s.sofa_file.filename().string();
        out << ": error " << format_number(s.criterion) << " (per step "
            << format_number(s.steps_compared > 0 ? s.criterion / double(s.steps_compared) : 0.0) << "), "
            << s.steps_compared << " steps compared";
        if (s.sofa_steps_not_compared > 0) out << " (" << s.sofa_steps_not_compared << " of SOFA's steps not exported)";
        out << "\n";
        if (!s.problem.empty()) out << "trajectory:   problem: " << s.problem << "\n";
        if (s.first_over_threshold) {
            all_within = false;
            out << "trajectory:   first step with |dx| > " << format_number(c.threshold) << ": "
                << describe_difference(*s.first_over_threshold) << "\n";
        } else if (s.steps_compared > 0) {
            out << "trajectory:   within " << format_number(c.threshold) << " at every step\n";
        }
        if (s.largest) out << "trajectory:   largest: " << describe_difference(*s.largest) << "\n";
        if (s.last) out << "trajectory:   at the end: " << describe_difference(*s.last) << "\n";
    }
    out << "trajectory: SOFA's criterion " << format_number(c.mean_criterion)
        << " (<= 1e-4; CompareState's sum over the compared steps), "
        << (all_within ? "every state within " : "states beyond ") << format_number(c.threshold)
        << (all_within ? " at every step: " : ": ") << (c.passed() ? "PASS" : "FAIL") << "\n";
    return out.str();
}

}  // namespace penalty::output
