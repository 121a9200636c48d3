"""Topological changes from Python (docs/topological-changes.md).

`TopologyMethods` gives penalty.Scene its topology methods; `modifier_method` gives the
SofaPython3 subset's topology modifiers (``TetrahedronSetTopologyModifier`` ...) their methods,
usable from a controller between steps (real SofaPython3 binds only ``addPoints`` and
``removePoints``; penalty also accepts SOFA's C++ names below).
"""

_KINDS = ("points", "edges", "triangles", "quads", "tetrahedra", "hexahedra")


class TopologyMethods:
    """Mixed into penalty.Scene."""

    def topologies(self):
        """Paths ("node path/container name") of the topologies that can change: each
        *SetTopologyContainer with a *SetTopologyModifier in its node."""
        return list(self._scene._dynamic_topologies())

    def topology(self, name: str) -> dict:
        """The current element lists of a dynamic topology (copies): points (count), edges,
        triangles, quads, tetrahedra, hexahedra ((n, k) int32 arrays), level, revision."""
        return self._scene._topology(name)

    def remove_elements(self, topology: str, kind: str, indices):
        """Removes elements of `kind` ("tetrahedra", "triangles", ...) from `topology` as SOFA's
        modifier does (the last element takes each removed one's index; faces, edges and points
        left without an element go too; every component follows). Between steps. ValueError
        (nothing changed) for an index out of range or repeated, or a component that cannot follow.
        A numpy view of a state keeps valid memory: after the state shrinks it still covers its old
        length (the rows past the new size are no longer the state's); after it grows, a view made
        before sees the state as it was (take a new one)."""
        self._scene._remove_elements(topology, kind, indices)

    def add_elements(self, topology: str, kind: str, elements=(), *, count: int = 0, ancestors=()):
        """Appends elements of `kind` (rows of vertex indices), creating the faces and edges they
        need; for "points", `count` points (each the mean of its `ancestors` list when given)."""
        self._scene._add_elements(topology, kind, elements, count, [list(a) for a in ancestors])


_MODIFIER_TYPES = {
    "PointSetTopologyModifier": "points", "EdgeSetTopologyModifier": "edges",
    "TriangleSetTopologyModifier": "triangles", "QuadSetTopologyModifier": "quads",
    "TetrahedronSetTopologyModifier": "tetrahedra", "HexahedronSetTopologyModifier": "hexahedra",
}


def _scene_and_topology(obj):
    root = obj._root()
    scene = getattr(root, "_penalty_scene", None) if root is not None else None
    if scene is None:
        raise RuntimeError(f"{obj._describe()}: call Sofa.Simulation.init(root) before changing the topology")
    node = obj.getContext()
    path = node._scene_path() if node is not None else "/"  # the built scene's path of the node
    return scene, path or "/"


def modifier_method(obj, name: str):
    """The SofaPython3-style method `name` of a topology modifier object, or None."""
    level = _MODIFIER_TYPES.get(obj._type)
    if level is None:
        return None

    def remover(kind, defaults):
        def remove(indices, *flags):
            if any(bool(f) != d for f, d in zip(flags, defaults)):
                raise NotImplementedError(f"{obj._describe()}.{name} with flags {flags}: penalty removes with "
                                          f"SOFA's removeItems flags {defaults} only")
            scene, path = _scene_and_topology(obj)
            scene.remove_elements(path, kind, list(indices))
        return remove

    def adder(kind):
        def add(elements, *unused):
            scene, path = _scene_and_topology(obj)
            scene.add_elements(path, kind, elements)
        return add

    def add_points(n, add_dof=True, *unused):
        if not add_dof:
            raise NotImplementedError(f"{obj._describe()}.addPoints(n, False): the states always follow")
        scene, path = _scene_and_topology(obj)
        scene.add_elements(path, "points", count=int(n))

    methods = {
        "removeItems": remover(level, ()),
        "removePoints": remover("points", (True,)),
        "removeEdges": remover("edges", (True,)),
        "removeTriangles": remover("triangles", (True, True)),
        "removeQuads": remover("quads", (True, True)),
        "removeTetrahedra": remover("tetrahedra", (True,)),
        "removeHexahedra": remover("hexahedra", ()),
        "addPoints": add_points,
        "addEdges": adder("edges"), "addTriangles": adder("triangles"), "addQuads": adder("quads"),
        "addTetrahedra": adder("tetrahedra"), "addHexahedra": adder("hexahedra"),
    }
    return methods.get(name)
