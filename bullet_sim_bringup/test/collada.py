"""Writes triangle meshes as COLLADA 1.4.1 (.dae) files with xml.etree, for worlds built by the tests.

Each part is (name, vertices, triangles, rgba): vertices in the file's unit, triangles as vertex indices
listed counter-clockwise seen from outside.
"""
import xml.etree.ElementTree as ET

NAMESPACE = "http://www.collada.org/2005/11/COLLADASchema"


def _sub(parent, tag, text=None, **attributes):
    element = ET.SubElement(parent, tag, {k.rstrip("_"): str(v) for k, v in attributes.items()})
    if text is not None:
        element.text = text
    return element


def _numbers(values):
    return " ".join("%.9g" % v for v in values)


def write_collada(path, parts, unit_name="meter", unit_meter=1.0, up_axis="Y_UP"):
    """Writes `parts` to `path`: one geometry, material and scene node per part."""
    root = ET.Element("COLLADA", {"xmlns": NAMESPACE, "version": "1.4.1"})
    asset = _sub(root, "asset")
    _sub(asset, "unit", name=unit_name, meter=unit_meter)
    _sub(asset, "up_axis", up_axis)
    effects = _sub(root, "library_effects")
    materials = _sub(root, "library_materials")
    geometries = _sub(root, "library_geometries")
    scene = _sub(_sub(root, "library_visual_scenes"), "visual_scene", id="scene")
    for name, vertices, triangles, rgba in parts:
        shading = _sub(_sub(_sub(effects, "effect", id=name + "-effect"), "profile_COMMON"), "technique",
                       sid="common")
        _sub(_sub(_sub(shading, "lambert"), "diffuse"), "color", _numbers(rgba))
        _sub(_sub(materials, "material", id=name + "-material"), "instance_effect", url="#" + name + "-effect")

        mesh = _sub(_sub(geometries, "geometry", id=name + "-mesh"), "mesh")
        source = _sub(mesh, "source", id=name + "-positions")
        flat = [c for vertex in vertices for c in vertex]
        _sub(source, "float_array", _numbers(flat), id=name + "-array", count=len(flat))
        accessor = _sub(_sub(source, "technique_common"), "accessor", source="#" + name + "-array",
                        count=len(vertices), stride=3)
        for axis in "XYZ":
            _sub(accessor, "param", name=axis, type="float")
        _sub(_sub(mesh, "vertices", id=name + "-vertices"), "input", semantic="POSITION",
             source="#" + name + "-positions")
        faces = _sub(mesh, "triangles", material="surface", count=len(triangles))
        _sub(faces, "input", semantic="VERTEX", source="#" + name + "-vertices", offset=0)
        _sub(faces, "p", " ".join(str(i) for triangle in triangles for i in triangle))

        node = _sub(scene, "node", id=name, name=name)
        instance = _sub(node, "instance_geometry", url="#" + name + "-mesh")
        _sub(_sub(_sub(instance, "bind_material"), "technique_common"), "instance_material", symbol="surface",
             target="#" + name + "-material")
    _sub(_sub(root, "scene"), "instance_visual_scene", url="#scene")
    ET.indent(root)
    ET.ElementTree(root).write(path, xml_declaration=True, encoding="utf-8")


def prism(corners, height, z0=0.0):
    """A vertical prism over the polygon `corners` ((x, y), counter-clockwise) from z0 to z0 + height."""
    n = len(corners)
    vertices = [(x, y, z0) for x, y in corners] + [(x, y, z0 + height) for x, y in corners]
    triangles = []
    for i in range(1, n - 1):
        triangles += [(0, i + 1, i), (n, n + i, n + i + 1)]  # bottom faces down, top faces up
    for i in range(n):
        j = (i + 1) % n
        triangles += [(i, j, n + j), (i, n + j, n + i)]
    return vertices, triangles
