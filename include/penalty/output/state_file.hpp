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
#include <fstream>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace penalty::output {

/// Writes the k-th state to DIR/<k>_<name>_mstate.txt (k from 0, name = sanitize_file_name of the
/// record's name, i.e. the name itself for ordinary names: SOFA's naming of regression files). The constructor creates DIR and truncates the files.
/// Throws std::runtime_error naming the path when a directory or file cannot be created/written,
/// std::invalid_argument for a null state or a state that is neither Vec3 nor Rigid3.
class StateExporter {
public:
    StateExporter(std::filesystem::path directory, std::vector<const StateRecord*> states);
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
    std::vector<std::unique_ptr<std::ofstream>> streams_;
};

/// The X line of one state as the state file writes it, without "  X= " and newline.
[[nodiscard]] std::string format_positions(const BaseState& state);

/// One sample of a state file.
struct StateSample {
    double time;
    std::vector<double> x;
};

/// Reads a state file. Blank lines are skipped, leading spaces ignored; "T= t" starts a sample,
/// "X= ..." gives its positions (exactly one per sample), "V= ..." lines (SOFA's writeV) are
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

}  // namespace penalty::output
