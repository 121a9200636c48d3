#pragma once
/// @file
/// The solve stage in one include: CG (cg_linear_solver.hpp), a solver subtree's system
/// (subtree_system.hpp), the ODE solvers (ode_solver.hpp) and the simulation with its step
/// (simulation.hpp).

#include "penalty/simulation/cg_linear_solver.hpp"
#include "penalty/simulation/ode_solver.hpp"
#include "penalty/simulation/simulation.hpp"
#include "penalty/simulation/solve_error.hpp"
#include "penalty/simulation/subtree_system.hpp"
