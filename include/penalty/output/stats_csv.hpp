#pragma once
/// @file
/// Per-step statistics as CSV, and helpers that compute them from the live scene.
///
/// File: a header line, then one row per write, comma-separated, numbers in shortest round-trip
/// form (format.hpp), integers in decimal:
///   step,time,contacts,active_contacts,max_penetration,contact_energy,kinetic_energy,
///   dissipated_energy,detection_seconds,response_seconds,solve_seconds,output_seconds,
///   cg_iterations,newton_iterations
/// (one line). Units: time s, max_penetration m, energies J, *_seconds wall-clock s.
/// With the tunnelling guard (beyond SOFA, docs/no-tunnelling.md) eight columns follow:
///   crossings,crossings_prevented,first_crossing,max_crossing_depth,solves,stiffened_contacts,
///   stiffening_energy,guard_seconds
/// crossings: those kept in the step's motion; crossings_prevented: found by solves the guard
/// undid; first_crossing: the earliest kept one, `kind model1:feature1 model2:feature2 toi` (""
/// when none; quoted when it holds a comma or a quote); max_crossing_depth m; solves: the solves
/// kept (1: the user's dt); stiffening_energy J (the step's); guard_seconds wall-clock s.

#include "penalty/output/state_record.hpp"
#include "penalty/output/vtk_writer.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <ostream>
#include <span>
#include <string>

namespace penalty::output {

struct StepStats {
    std::int64_t step = 0;
    double time = 0.0;  ///< s
    std::size_t contacts = 0;
    std::size_t active_contacts = 0;
    double max_penetration = 0.0;    ///< m, 0 if none
    double contact_energy = 0.0;     ///< J
    double kinetic_energy = 0.0;     ///< J
    double dissipated_energy = 0.0;  ///< J, cumulative
    double detection_seconds = 0.0;
    double response_seconds = 0.0;
    double solve_seconds = 0.0;
    double output_seconds = 0.0;
    int cg_iterations = 0;      ///< CG iterations of the step, every implicit solver
    int newton_iterations = 0;  ///< Newton iterates of the step (0 without Newton)
    /// The tunnelling guard's columns (written only by a writer made with them).
    struct Tunnelling {
        std::size_t crossings = 0;
        std::size_t prevented = 0;
        std::string first_crossing;  ///< "" when none
        double max_depth = 0.0;      ///< m
        int solves = 1;
        std::size_t stiffened_contacts = 0;
        double stiffening_energy = 0.0;  ///< J
        double guard_seconds = 0.0;
    } tunnelling;
};

/// The CSV header line (without newline); with the tunnelling guard's columns when asked.
[[nodiscard]] const char* stats_csv_header();
[[nodiscard]] std::string stats_csv_header(bool tunnelling_columns);

class StatsCsvWriter {
public:
    /// Creates the parent directory and the file (truncated) and writes the header (with the
    /// tunnelling guard's columns when `tunnelling_columns`).
    /// Throws std::runtime_error naming the path on failure.
    explicit StatsCsvWriter(const std::filesystem::path& file, bool tunnelling_columns = false);
    /// Appends one row and flushes. A non-finite value throws NonFiniteValueError naming the
    /// column and the step (nothing written); an I/O failure throws std::runtime_error.
    void write(const StepStats& stats);

    [[nodiscard]] const std::filesystem::path& file() const { return file_; }

private:
    std::filesystem::path file_;
    std::unique_ptr<std::ostream> stream_;
    bool tunnelling_columns_ = false;
};

/// The row write() appends (without newline), after the same finiteness check.
[[nodiscard]] std::string format_stats_row(const StepStats& stats, bool tunnelling_columns = false);

struct ContactSummary {
    std::size_t contacts = 0;         ///< Σ field->size()
    std::size_t active_contacts = 0;  ///< Σ field->active_count() (pen > 0 at the last add_force)
    double max_penetration = 0.0;     ///< max(0, max pen of export_contacts at the current positions) (m)
    double contact_energy = 0.0;      ///< Σ field->potential_energy() (J)
    double dissipated_energy = 0.0;   ///< Σ field->dissipated_energy() (J, cumulative)
};

/// Sums over the records (a null field or state throws std::invalid_argument).
[[nodiscard]] ContactSummary summarize_contacts(std::span<const ContactRecord> contacts);

/// Σ ½ vᵀ M v (J) over the records that have a mass (StateRecord::mass->kinetic_energy());
/// records without a mass contribute nothing (a mapped state's motion is counted through the
/// mass of the state it is mapped from, a static state has no mass).
[[nodiscard]] double kinetic_energy(std::span<const StateRecord> states);

}  // namespace penalty::output
