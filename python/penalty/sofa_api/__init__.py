"""penalty's implementation of SofaPython3's API (Sofa, Sofa.Core, Sofa.Simulation, Sofa.Helper,
Sofa.Gui, SofaRuntime): `import Sofa` in a scene script resolves to the thin modules of
sofa_compat/, which re-export this package. A script builds a tree of Node and Object;
Sofa.Simulation.init builds the C++ scene from it (the one scene builder of `.scn` files) and from
then on every node and component is live: its Data read and write the running simulation
(docs/python.md, "The object model")."""
from .components import (ArrayData, Controller, DataEngine, ForceFieldRigid3d, ForceFieldVec3d,  # noqa: F401
                         Mapping_Rigid3d_Vec3d, Mapping_Vec3d_Vec1d, Mapping_Vec3d_Vec3d, dispatch)
from .data import Data, DataContainer, DataString, Link, LinkPath  # noqa: F401
from .graph import Base, NodeIterator  # noqa: F401
from .script import ScriptError, ScriptExit, import_sofa_python_scene, run_scene_script  # noqa: F401
from .simulation import (animate, animateNSteps, init, initRoot, load, reset, send_event,  # noqa: F401
                         unload)
from .text import to_sofa_text  # noqa: F401
from .tree import Node, Object  # noqa: F401
