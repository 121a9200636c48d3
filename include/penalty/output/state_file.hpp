#pragma once
/// @file
/// SOFA's regression state files (WriteState / CompareState format) and SOFA's regression
/// comparison.
///
/// File layout, one sample per written time (n DOFs):
///     T= <time>\n
///       X= <v0> <v1> ... <vN-1>\n          (two spaces, "X= ", values separated by one space)
/// with per DOF "x y z" (Vec3) or "x y z qx qy qz qw" (Rigid3: centre then quaternion).
/// A state with no DOF writes "  X= \n". Numbers: shortest round-trip form (format.hpp); SOFA
/// writes ostream's default 6 significant digits in the same layout.

#include "penalty/output/state_record.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace penalty::output {

/// Writes the k-th state to DIR/<k>_<name>_mstate.txt (k from 0, name = sanitize_file_name of the
/// record's name, i.e. the name itself for ordinary names: SOFA's naming of regression files). The constructor creates
/// DIR and truncates the files. Throws std::runtime_error naming the path when a directory or file cannot be
/// created/written, std::invalid_argument for a null state or a state that is neither Vec3 nor Rigid3.
class StateExporter {
public:
    StateExporter(const std::filesystem::path& directory, std::vector<const StateRecord*> states);
    ~StateExporter();
    StateExporter(StateExporter&&) noexcept;
    StateExporter& operator=(StateExporter&&) noexcept;

    /// Appends "T= <time>\n  X= <positions>\n" to every file and flushes.
    /// Every position is checked first: a non-finite value throws NonFiniteValueError naming the
    /// state, the DOF and the time, and nothing is written for this time in any file.
    void write(double time);

    [[nodiscard]] const std::vector<std::filesystem::path>& files() const { return files_; }
    /// values_per_dof() of each state, in file order (for compare_with_reference).
    [[nodiscard]] const std::vector<int>& values_per_dof() const { return values_per_dof_; }

private:
    std::vector<const StateRecord*> states_;
    std::vector<std::filesystem::path> files_;
    std::vector<int> values_per_dof_;
    std::vector<std::unique_ptr<std::ostream>> streams_;
};

/// The X line of one state as the state file writes it, without "  X= " and newline.
[[nodiscard]] std::string format_positions(const BaseState& state);

/// One sample of a state file.
struct StateSample {
    double time;
    std::vector<double> x;
};

/// Reads a state file (gzip-compressed when its name ends in ".gz"). Blank lines are skipped, leading spaces ignored;
/// "T= t" starts a sample, "X= ..." gives its positions (exactly one per sample), "V= ..." lines (SOFA's writeV) are
/// ignored. Throws std::runtime_error "<file>:<line>: <reason>" for an unreadable file, a number
/// that does not parse, an X line before any T line, a second X line for one time, a sample
/// without X, or an unknown keyword.
[[nodiscard]] std::vector<StateSample> read_state_file(const std::filesystem::path& file);

/// SOFA's regression comparison.
///
/// For state s with reference samples (T_r, Xref_r) and our samples (t_j, X_j):
///   error_s = ( Σ_r Σ_i |X_i(T_r) − Xref_i(T_r)| ) / n_dofs
/// where X(T_r) is our sample closest to T_r within max(1e-9·max(1, |T_r|), half a unit of the 6th
/// significant digit of T_r) (SOFA writes 6 significant digits), i runs over the scalars of the
/// X line (3 per Vec3 DOF, 7 per Rigid3 DOF: the quaternion components are compared as numbers),
/// and n_dofs = (values on the first reference X line) / values_per_dof[s]; n_dofs = 0 gives
/// error 0.
///   mean_error = Σ_s error_s / (number of states)   (0 when there is no state)
/// The run passes when no message was produced and mean_error ≤ 1e-4 (RegressionResult::passed).
/// Our samples at times absent from the reference are ignored.
///
/// The first error of a state produces a message naming the file (and time) and sets that
/// state's error to +inf (the state's comparison stops there):
/// unreadable or malformed file, empty reference, a reference time without our sample, X lines
/// of different lengths, a reference line length not a multiple of values_per_dof, a non-finite
/// value. Different numbers of reference and our files is a message; only the common prefix is
/// compared and mean_error is +inf. values_per_dof must have one positive entry per reference
/// file (3 for Vec3, 7 for Rigid3; StateExporter::values_per_dof()), else std::invalid_argument.
struct RegressionResult {
    std::vector<double> per_state_error;
    double mean_error = 0.0;
    std::vector<std::string> messages;
    /// SOFA's verdict: no message and mean_error ≤ tolerance.
    [[nodiscard]] bool passed(double tolerance = 1e-4) const { return messages.empty() && mean_error <= tolerance; }
};

[[nodiscard]] RegressionResult compare_with_reference(std::span<const std::filesystem::path> reference_files,
                                                      std::span<const std::filesystem::path> our_files,
                                                      std::span<const int> values_per_dof);

/// The per-state term of compare_with_reference on samples already read; `label` names the state
/// in messages, which are appended to `messages`. Returns error_s (+inf on error).
[[nodiscard]] double state_regression_error(std::span<const StateSample> reference, std::span<const StateSample> ours,
                                            int values_per_dof, const std::string& label,
                                            std::vector<std::string>& messages);

/// The largest difference between two samples of a state at one step.
struct StepDifference {
    std::size_t step = 0;         ///< index of the sample in SOFA's file (step k: state at T = k·dt)
    double time = 0.0;            ///< s
    std::size_t value_index = 0;  ///< index in the X line
    double max_difference = 0.0;  ///< max_i |X_i − Xsofa_i| (+inf for a NaN)
    std::size_t dof = 0;          ///< value_index / values_per_dof
    std::size_t component = 0;    ///< value_index % values_per_dof (0..2 x y z, 3..6 qx qy qz qw)
};

/// One exported state against SOFA's trajectory of it (every sample of SOFA's file whose time
/// we exported, times matched within 1e-9·max(1, |T|); SOFA's samples at other times, e.g. beyond
/// our last step, are counted, not compared). criterion is SOFA's error_s over the compared
/// samples: Σ_T Σ_i |X_i(T) − Xsofa_i(T)| / n_dofs (as compare_with_reference).
struct TrajectoryStateComparison {
    std::filesystem::path sofa_file, our_file;
    double criterion = 0.0;  ///< SOFA's error_s (compare_with_reference)
    std::size_t steps_compared = 0;
    std::size_t sofa_steps_not_compared = 0;             ///< SOFA samples at times we did not export
    std::optional<StepDifference> first_over_threshold;  ///< first step with max|Δx| > threshold
    std::optional<StepDifference> largest;               ///< the step with the largest max|Δx|
    std::optional<StepDifference> last;                  ///< the last compared step
    std::string problem;                                 ///< unreadable file, missing time, ... ("" if none)
};

/// Every exported state against SOFA's trajectory (`penalty run --compare-trajectory DIR`).
struct TrajectoryComparison {
    std::vector<TrajectoryStateComparison> states;
    double mean_criterion = 0.0;        ///< SOFA's criterion: mean of the states' error_s
    double threshold = 1e-12;           ///< m (or quaternion units) per value
    std::vector<std::string> messages;  ///< file pairing problems; "note: ..." ones are informative
    [[nodiscard]] bool messages_are_notes() const;
    /// No pairing problem, every state compared at least once, SOFA's criterion ≤ tolerance and
    /// no state above the threshold at any step.
    [[nodiscard]] bool passed(double criterion_tolerance = 1e-4) const;
};

/// SOFA's state files in `directory` for our files `<k>_<name>_mstate.txt`: the file
/// `<k>_<name>_mstate.txt` or `.txt.gz` (a name that differs from ours only by the characters
/// sanitize_file_name replaces), else the one file of index k (a note is added to `messages`).
/// A missing index gives an empty path and a message. Throws std::runtime_error when
/// `directory` does not exist.
[[nodiscard]] std::vector<std::filesystem::path> find_trajectory_files(const std::filesystem::path& directory,
                                                                       std::span<const std::filesystem::path> our_files,
                                                                       std::vector<std::string>& messages);

/// One state's comparison on samples already read (SOFA's first, ours second).
[[nodiscard]] TrajectoryStateComparison compare_state_trajectory(std::span<const StateSample> sofa,
                                                                 std::span<const StateSample> ours, int values_per_dof,
                                                                 double threshold);

/// Reads SOFA's files of `sofa_directory` (plain or .gz) and our exported files and compares
/// them step by step. values_per_dof: one per file (StateExporter::values_per_dof()).
[[nodiscard]] TrajectoryComparison compare_trajectories(const std::filesystem::path& sofa_directory,
                                                        std::span<const std::filesystem::path> our_files,
                                                        std::span<const int> values_per_dof, double threshold = 1e-12);

/// The report printed by `--compare-trajectory`: per state, SOFA's error, the first step above
/// the threshold (step, time, DOF, component, difference), the largest difference and the
/// difference at the last step; then SOFA's criterion and the verdict, e.g.
///   trajectory: 0_Particles_mstate.txt: error 1.2e-10; first step > 1e-12: 23 (t = 0.23 s) DOF 5 y, 3.1e-12; ...
///   trajectory: SOFA's criterion 1.2e-10 (<= 1e-4), every state within 1e-12 at every step: PASS
[[nodiscard]] std::string format_trajectory_comparison(const TrajectoryComparison& comparison);

}  // namespace penalty::output
