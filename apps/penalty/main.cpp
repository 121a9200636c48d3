// `penalty`: command-line entry point.
// Until the scene runner lands, the main job is `penalty demo`: the penalty force field on real
// numbers (two bodies pressed together, then a damped, frictional drop), run by default.
#include "demo.hpp"

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
    CLI::App app{"penalty: fast, validated penalty-based contact for deformable and rigid bodies"};
    app.require_subcommand(0, 1);
    auto* demo = app.add_subcommand("demo", "Built-in demonstration of the penalty force field (default)");
    penalty::apps::DemoOptions options;
    demo->add_option("--stiffness", options.stiffness, "Contact stiffness ks (N/m)")
        ->check(CLI::PositiveNumber);
    demo->add_option("--damping", options.damping, "Normal damping c (N·s/m) of the drop")
        ->check(CLI::NonNegativeNumber);
    demo->add_option("--friction", options.friction, "Friction coefficient mu (static = dynamic) of the drop")
        ->check(CLI::NonNegativeNumber);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        return penalty::apps::run_demo(options, std::cout);
    } catch (const std::exception& e) {
        std::cerr << "penalty: error: " << e.what() << "\n";
        return 1;
    }
}
