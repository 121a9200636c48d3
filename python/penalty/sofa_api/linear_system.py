"""SofaPython3's views of a linear system (Sofa.SofaLinearSystem, Sofa.SofaLinearSolver; docs/python.md):
the methods `A()`, `b()`, `x()` (and `get_system_matrix`, `get_rhs_vector`, `get_solution_vector`) of
a MatrixLinearSystem, ConstantSparsityPatternSystem or CompositeLinearSystem, and `A()`, `b()`, `x()`
of a linear solver, over the last step's solve of the EulerImplicitSolver above them
(python/src/linear_system_bindings.cpp).

SofaPython3's semantics (bindings/Modules/src/SofaPython3/SofaLinearSystem/Binding_LinearSystem.cpp,
SofaLinearSolver/Binding_LinearSolver.cpp): A is the assembled matrix A = m·M + b·B + k·K with the
projective constraints applied (a row and column of a fixed DOF cleared, 1 on its diagonal), as a
scipy.sparse.csr_matrix (a dense numpy array for the FullMatrix template); b the right-hand side and
x the solution of A·x = b, numpy vectors. A MatrixLinearSystem assembles what its assembleMass,
assembleDamping, assembleStiffness and applyProjectiveConstraints say, with the solve's factors; a
system a CompositeLinearSystem feeds but does not solve has A only (b and x are empty).
"""
from __future__ import annotations

SYSTEM_TYPES = ("MatrixLinearSystem", "ConstantSparsityPatternSystem", "CompositeLinearSystem")
SOLVER_TYPES = ("SparseLDLSolver", "AsyncSparseLDLSolver", "EigenSimplicialLDLT", "EigenSimplicialLLT",
                "SparseCholeskySolver", "CholeskySolver", "EigenSparseLU", "SparseLUSolver", "EigenSparseQR",
                "CGLinearSolver")

_SYSTEM_METHODS = {"A": "A", "get_system_matrix": "A", "b": "b", "get_rhs_vector": "b", "x": "x",
                   "get_solution_vector": "x"}
_SOLVER_METHODS = {"A": "A", "b": "b", "x": "x"}


def _flag(obj, name: str) -> bool:
    data = obj.findData(name)
    if data is None:
        return True
    value = data.value
    if isinstance(value, str):
        return value.strip().lower() not in ("0", "false")
    return bool(value)


def _all_objects(node):
    for o in node.objects:
        yield o
    for child in node.children:
        yield from _all_objects(child)


def _linked(link):
    """The objects a link (Sofa.Core.Link) names, in order."""
    if link is None:
        return []
    out = []
    for index in range(link.getSize()):
        base = link.getLinkedBase(index)
        if base is not None:
            out.append(base)
    return out


def _is_solved(system) -> bool:
    """False for a system a CompositeLinearSystem feeds without solving it (SOFA's
    CompositeLinearSystem::l_solverLinearSystem names the solved one)."""
    root = system._root()
    if root is None:
        return True
    for o in _all_objects(root):
        if getattr(o, "_type", "") != "CompositeLinearSystem":
            continue
        members = _linked(o.findLink("linearSystems"))
        solved = _linked(o.findLink("solverLinearSystem"))
        target = solved[0] if solved else (members[0] if members else None)
        if any(m is system for m in members) and target is not system:
            return False
    return True


def _dense(obj) -> bool:
    return (obj.getTemplateName() or "") == "FullMatrix"


def _view(obj, name: str, what: str):
    live = obj._require_live(name)
    if obj._type in SYSTEM_TYPES and obj._type != "CompositeLinearSystem":
        flags = {key: _flag(obj, data) for key, data in (("mass", "assembleMass"), ("damping", "assembleDamping"),
                                                          ("stiffness", "assembleStiffness"),
                                                          ("projective", "applyProjectiveConstraints"),
                                                          ("mapped", "applyMappedComponents"))}
        solved = _is_solved(obj)
    else:
        flags, solved = {}, True
    out = live._linear_system(obj._scene_path(), solved=solved, dense=_dense(obj), **flags)
    return out[what]


def linear_system_method(obj, name: str):
    """The SofaPython3 view method `name` of a linear system or linear solver object, or None."""
    if obj._type in SYSTEM_TYPES:
        what = _SYSTEM_METHODS.get(name)
    elif obj._type in SOLVER_TYPES:
        what = _SOLVER_METHODS.get(name)
    else:
        return None
    if what is None:
        return None

    def view():
        return _view(obj, name, what)

    view.__name__ = name
    view.__doc__ = f"{obj._type}.{name}(): the last solve's {what} (SofaPython3's linear system view)"
    return view
