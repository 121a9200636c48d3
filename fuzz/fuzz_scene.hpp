#pragma once
/// @file
/// The scene fuzz targets' body: parse the input as a `.scn` file, build it as `penalty info`
/// does, and optionally step it. Every refusal must be one of the documented exceptions: while
/// building, a LoadError naming the file; while running, also a divergence or the runner's
/// std::runtime_error ("other error", exit 5). Anything else, a crash, a leak or a sanitizer
/// report is a finding. (Structural problems found at step 0 used to be exit-5 errors and were
/// moved to the build one by one as the fuzzer found them: see fuzz/regressions/.)

#include "penalty/io/error.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/output/format.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

namespace penalty::fuzz {

inline int run_scene_input(const std::uint8_t* data, std::size_t size, std::int64_t steps) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::unique_ptr<scene::Scene> built;
    try {
        scene::BuildOptions options;
        options.threads = 1;
        // Small caps keep every input fast: the caps themselves are what is tested here, not
        // whether a legitimate 10⁷-DOF scene runs within the fuzzer's time-out.
        options.max_dofs = 5'000;
        options.max_cg_iterations = 200;
        built = scene::build_scene(io::parse_scene_string(text, "fuzz.scn"), options);
        (void)scene::describe_scene(*built);
    } catch (const io::LoadError&) {
        return 0;  // a located refusal: the expected answer to bad input
    }
    if (steps == 0) return 0;
    try {
        scene::RunOptions run;
        run.steps = steps;
        (void)scene::run_scene(*built, run);
    } catch (const io::LoadError&) {                // a parameter too large, found at the first step
    } catch (const output::NonFiniteValueError&) {  // diverged
    } catch (const NonFiniteSolveError&) {          // diverged inside a solve
    } catch (const std::runtime_error&) {           // the runner's "other error" (exit 5) with a message
    }
    return 0;
}

}  // namespace penalty::fuzz
