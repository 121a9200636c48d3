#pragma once
// Built-in demonstration of the penalty force field (the main job until the scene runner lands).
#include <iosfwd>

namespace penalty::apps {

struct DemoOptions {
    double stiffness = 1000.0;  ///< ks (N/m)
    double damping = 4.0;       ///< c (N·s/m) for the drop
    double friction = 0.3;      ///< mu_s = mu_v for the drop
};

/// Prints the demonstration to `out`; returns the process exit code (0 when the energy balance
/// of the drop closes to 1%).
int run_demo(const DemoOptions& options, std::ostream& out);

}  // namespace penalty::apps
