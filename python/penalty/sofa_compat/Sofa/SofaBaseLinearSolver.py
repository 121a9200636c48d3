"""penalty's Sofa.SofaBaseLinearSolver (SofaPython3's module of the same name): the views of a solve's linear system
are methods of the components themselves, A(), b(), x() (penalty/sofa_api/linear_system.py,
docs/python.md). The module holds no names of its own: SofaPython3's holds the bound C++ classes."""
from penalty.sofa_api.linear_system import SOLVER_TYPES, SYSTEM_TYPES  # noqa: F401
