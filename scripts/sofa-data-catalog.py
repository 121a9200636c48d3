#!/usr/bin/python3
"""Writes the catalog of the Data and links SOFA declares for every component type of penalty's
registry: src/scene/sofa_data_catalog.tsv (read by the live data layer, src/scene/live_data.cpp).

Run it with real SofaPython3 (../shared/sofa-head/sofa-head-python scripts/sofa-data-catalog.py TYPES OUT),
TYPES one type name a line (`penalty info --components` lists them). For each type it creates the
component, uninitialised, in a node that has a Vec3d (and, for a second row set, a Rigid3d)
MechanicalObject and a MeshTopology, and records per Data: its name, SOFA's value type
(BaseData::getValueTypeString), its value before init (the default, BaseData::getValueString) and
how SofaPython3 presents the value (python_form); per link: its name and value. Only names, types and defaults are recorded
(interface facts), never SOFA's help texts.

Output: one line per (type, template, data):
`type<TAB>template<TAB>kind<TAB>name<TAB>value type<TAB>Python form<TAB>default`
with kind `data`, `link`; tabs and newlines of a default are written as \\t and \\n.
"""
import sys

import Sofa
import Sofa.Core
import SofaRuntime

SofaRuntime.importPlugin("Sofa.Component")
SofaRuntime.importPlugin("Sofa.GL.Component")


def escape(text):
    return text.replace("\\", "\\\\").replace("\t", "\\t").replace("\n", "\\n")


def python_form(data):
    """How SofaPython3 presents the value: float, int, str, or ndarray:<dtype>:<ndim>; else the
    Python type's name."""
    try:
        value = data.value
    except Exception:  # noqa: BLE001 - a Data SofaPython3 cannot convert
        return "none"
    if hasattr(value, "dtype") and hasattr(value, "ndim"):
        return f"ndarray:{value.dtype}:{value.ndim}"
    return type(value).__name__


def record(out, type_name, template, obj, links=True, same_as=None):
    rows = []
    for d in obj.getDataFields():
        rows.append(("data", d.getName(), d.getValueTypeString(), python_form(d), d.getValueString()))
    if links:
        for link in obj.getLinks():
            rows.append(("link", link.getName(), "link", "link", link.getValueString()))
    if same_as is not None and same_as.get(type_name) == rows:
        return 0  # the Rigid3d version declares what the Vec3d one does: its rows stand
    if same_as is not None and template == "Vec3d":
        same_as[type_name] = rows
    for kind, name, value_type, form, default in rows:
        out.write("\t".join([type_name, template, kind, name, value_type, form, escape(default)]) + "\n")
    return len(rows)


# Mappings need their input and output to be created; topological mappings their two topologies.
TOPOLOGICAL_MAPPINGS = {
    "Tetra2TriangleTopologicalMapping": ("TetrahedronSetTopologyContainer", "TriangleSetTopologyContainer"),
    "Hexa2QuadTopologicalMapping": ("HexahedronSetTopologyContainer", "QuadSetTopologyContainer"),
    "Triangle2EdgeTopologicalMapping": ("TriangleSetTopologyContainer", "EdgeSetTopologyContainer"),
    "Quad2TriangleTopologicalMapping": ("QuadSetTopologyContainer", "TriangleSetTopologyContainer"),
    "Hexa2TetraTopologicalMapping": ("HexahedronSetTopologyContainer", "TetrahedronSetTopologyContainer"),
}


def create(node, type_name, template):
    if type_name in TOPOLOGICAL_MAPPINGS:
        source, target = TOPOLOGICAL_MAPPINGS[type_name]
        node.addObject(source, name="from_topology")
        sub = node.addChild("to")
        sub.addObject(target, name="to_topology")
        return sub.addObject(type_name, input="@../from_topology", output="@to_topology")
    if type_name.endswith("Mapping"):
        node.addObject("MechanicalObject", name="mapped", template="Vec3d", position=[0, 0, 0])
        return node.addObject(type_name, input="@../MechanicalObject", output="@mapped")
    if type_name == "MechanicalObject":
        return node.addObject(type_name, template=template)
    return node.addObject(type_name)


def main():
    types = [t.strip() for t in open(sys.argv[1]) if t.strip()]
    out = open(sys.argv[2], "w")
    failed = []
    vec3_rows = {}
    for template in ("Vec3d", "Rigid3d"):
        for type_name in types:
            root = Sofa.Core.Node("root")
            node = root.addChild("n")
            node.addObject("MechanicalObject", template=template, position=[0, 0, 0] + ([0, 0, 0, 1] if template == "Rigid3d" else []))
            node.addObject("MeshTopology", position=[0, 0, 0])
            child = node.addChild("c")
            try:
                obj = create(child, type_name, template)
            except Exception as e:  # noqa: BLE001 - a type SOFA does not know, or not for this template
                failed.append(f"{type_name} ({template}): {str(e).splitlines()[0] if str(e) else type(e).__name__}")
                continue
            obj_template = obj.getTemplateName() if hasattr(obj, "getTemplateName") else ""
            if template == "Rigid3d" and "Rigid" not in obj_template.split(",")[0]:
                continue  # the component has no Rigid3d version: the Vec3d rows stand
            record(out, type_name, template, obj, same_as=vec3_rows)
    # Nodes (their Data only: SOFA's node links are its lists of children and objects).
    record(out, "Node", "", Sofa.Core.Node("root"), links=False)
    # SofaPython3's Python component classes, by their Sofa.Core names.
    for name in ("Controller", "DataEngine", "ForceFieldVec3d", "ForceFieldRigid3d", "Mapping_Vec3d_Vec3d",
                 "Mapping_Rigid3d_Vec3d"):
        try:
            record(out, name, "", getattr(Sofa.Core, name)(name="c"))
        except Exception as e:  # noqa: BLE001
            failed.append(f"Sofa.Core.{name}: {e}")
    out.close()
    for f in failed:
        print("not created:", f, file=sys.stderr)


if __name__ == "__main__":
    main()
