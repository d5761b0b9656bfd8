# SPDX-License-Identifier: GPL-3.0-or-later
"""X_ITE as a peer of the comparison (issue 36 item 4): the scene written as an X3D file, that
file rendered by the X3D browser X_ITE in headless Chromium (``core/x_ite.py``) at the
comparison's size.  The file and the page stay in the report folder (``x_ite/scene.x3d``,
``x_ite/scene.html``).

The file is written from what the comparison itself reads (``describe.describe``: the lights
as Blender evaluates them, Light Linking as light sets) and from each object's evaluated
triangles with Blender's corner normals in world space (``threejs_export._mesh_arrays``), with
``core/x3d.py``'s writer:

* the scene camera as the bound Viewpoint, in Blender's world axes (a Viewpoint looks along
  its -Z with +Y up, as a Blender camera does): ``fieldOfView`` is the angle of the picture's
  smaller side read from Blender's own projection (``calc_matrix_camera``); an orthographic
  camera is an OrthoViewpoint; NavigationInfo ``headlight FALSE`` (a scene's headlight is a
  Sun that follows the camera: it is exported as the DirectionalLight it is);
* each Phong material as a Material: diffuseColor = Object Color, ambientIntensity = Ambient
  Object Color / Object Color, specularColor, shininess = Exponent / 128, emissiveColor =
  Irradiant Color, transparency = 1 - Opacity;
* each light with its X3D settings (intensity, ambientIntensity, attenuation, radius,
  beamWidth, cutOffAngle = half the spot size); when the objects do not all see the same
  lights, each light set is a Group holding its shapes and scoped copies of its lights
  (``global FALSE``).

What X3D cannot say is a warning in metrics.json: an Ambient Object Color that is not a
multiple of Object Color, an exponent above 128, the World's Phong ambient (X3D has no global
ambient light), a texture on a control (its control's value is written), a camera shift.
"""

from __future__ import annotations

import math
import os

import numpy as np

from ...core import x3d, x_ite
from ..interchange import threejs_export
from ..lighting import materials

#: X3D's largest exponent: 128 × shininess with shininess ≤ 1.
MAX_EXPONENT = 128.0


def render(scene, layer, objects, data, width: int, height: int, folder: str) -> tuple:
    """(X_ITE's RGBA picture (row 0 at the top; its canvas holds the equation's I), seconds in
    the browser, warnings): the scene written into *folder*/x_ite/scene.x3d and rendered."""
    path = os.path.join(folder, "x_ite", "scene.x3d")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    warnings = write(scene, layer, objects, data, width, height, path)
    result = x_ite.render_file(path, width, height,
                               page_path=os.path.join(folder, "x_ite", "scene.html"))
    return result.rgba, result.seconds, warnings + [f"X_ITE: {e}" for e in result.errors]


def write(scene, layer, objects, data, width: int, height: int, path: str) -> list:
    """Write *scene* (its Phong *objects*, described as *data*) as X3D XML to *path*; returns
    the warnings."""
    doc, warnings = document(scene, layer, objects, data, width, height)
    x3d.save(doc, path)
    return warnings


def _vec(values) -> tuple:
    return tuple(float(v) for v in values)


def viewpoint(camera: dict, width: int, height: int, warnings: list) -> x3d.Viewpoint:
    """The Viewpoint of ``threejs_export.camera_dict``'s camera (column-major matrices)."""
    matrix = np.array(camera["matrix_world"], np.float64).reshape(4, 4).T
    projection = np.array(camera["projection"], np.float64).reshape(4, 4).T
    rotation = matrix[:3, :3] / np.linalg.norm(matrix[:3, :3], axis=0)
    parts = x3d.decompose(np.block([[rotation, np.zeros((3, 1))], [np.zeros((1, 3)), 1.0]]))
    view = x3d.Viewpoint(name="Camera", position=_vec(matrix[:3, 3]),
                         orientation=_vec(parts["rotation"]))
    sx, sy = projection[0, 0], projection[1, 1]
    if camera["type"] == "orthographic":
        cx, cy = -projection[0, 3] / sx, -projection[1, 3] / sy
        view.kind = "OrthoViewpoint"
        view.ortho_field = (cx - 1.0 / sx, cy - 1.0 / sy, cx + 1.0 / sx, cy + 1.0 / sy)
        return view
    if abs(projection[0, 2]) > 1e-9 or abs(projection[1, 2]) > 1e-9:
        warnings.append("the camera's shift is not exported (an X3D Viewpoint has none)")
    # fieldOfView: the angle of the smaller side of the picture (ISO/IEC 19775-1 §23.4.2)
    view.field_of_view = 2.0 * math.atan(1.0 / (sy if width >= height else sx))
    return view


def material(mat, warnings: list) -> x3d.Material:
    """The X3D Material of a Phong material's control values."""
    node = mat.node_tree.nodes[materials.LIGHTS_NODE]

    def value(name):
        return threejs_export._input_value(node, name, warnings, mat)  # noqa: SLF001

    diffuse = np.array(value("Object Color"), np.float64)
    ambient = np.array(value(materials.AMBIENT_INPUT), np.float64)
    ratios = [a / d for a, d in zip(ambient, diffuse) if d > 1e-6]
    ambient_intensity = float(np.mean(ratios)) if ratios else 0.0
    if np.abs(ambient_intensity * diffuse - ambient).max() > 1e-6 or ambient_intensity > 1.0:
        warnings.append(f"{mat.name}: its Ambient Object Color is not ambientIntensity × "
                        "Object Color (0 ≤ ambientIntensity ≤ 1): X3D says "
                        f"ambientIntensity {min(ambient_intensity, 1.0):.4g}")
    exponent = float(value("Exponent"))
    if exponent > MAX_EXPONENT:
        warnings.append(f"{mat.name}: Exponent {exponent:g} is above X3D's 128 (shininess 1)")
    return x3d.Material(name=mat.name, diffuse=_vec(diffuse),
                        ambient_intensity=min(max(ambient_intensity, 0.0), 1.0),
                        specular=_vec(value("Specular Color")),
                        emissive=_vec(value("Irradiant Color")),
                        shininess=min(max(exponent / MAX_EXPONENT, 0.0), 1.0),
                        transparency=1.0 - materials.opacity(mat))


def light(entry: dict, scoped: bool) -> x3d.Light:
    """The X3D light of one light of ``describe.describe`` (the X3D model's settings)."""
    kind = entry["type"]
    out = x3d.Light(kind=kind, name=entry["name"], intensity=float(entry["intensity"]),
                    ambient_intensity=float(entry.get("ambient", 0.0)),
                    color=_vec(entry["color"]), is_global=not scoped)
    if kind in ("directional", "spot"):
        u = np.asarray(entry["direction"], np.float64)
        out.direction = _vec(u / np.linalg.norm(u))
    if kind in ("point", "spot"):
        out.location = _vec(entry["position"])
        out.attenuation = (float(entry.get("constant", 1.0)), float(entry.get("linear", 0.0)),
                           float(entry.get("quadratic", 0.0)))
        out.radius = float(entry.get("radius", 100.0))
    if kind == "spot":
        out.cut_off_angle = math.radians(entry["half_angle"])
        out.beam_width = float(entry.get("beam_width", out.cut_off_angle))
    return out


def document(scene, layer, objects, data, width: int, height: int) -> tuple:
    """(the core.x3d.Document of the scene, warnings)."""
    warnings = []
    if data.get("model") != "x3d":
        warnings.append(f"scene {scene.name!r} is not in the X3D model: X_ITE shows the X3D "
                        "equation, not the scene's")
    if data["ambient"]["intensity"] > 0.0:
        warnings.append("the World's Phong ambient is not exported (X3D has no global ambient "
                        "light)")
    depsgraph = layer.depsgraph
    doc = x3d.Document(title=data.get("title", ""), headlight=False,
                       navigation_types=["NONE"])
    doc.viewpoint = viewpoint(threejs_export.camera_dict(scene, depsgraph, width, height),
                              width, height, warnings)
    sets = sorted({tuple(entry["lights"]) for entry in data["objects"]})
    scoped = len(sets) > 1
    groups = {}
    for light_set in sets:
        group = x3d.Transform(kind="Group", name=f"lights_{'_'.join(map(str, light_set))}")
        if scoped:
            group.children.extend(light(data["lights"][k], True) for k in light_set)
        groups[light_set] = group
    if not scoped:
        doc.root.children.extend(light(entry, False) for entry in data["lights"])
    doc.root.children.insert(0, doc.viewpoint)
    made = {}
    for obj, entry in zip(objects, data["objects"]):
        points, normals, slots = threejs_export._mesh_arrays(obj, depsgraph)  # noqa: SLF001
        for slot_index in np.unique(slots):
            slot = obj.material_slots[int(slot_index)] if obj.material_slots else None
            mat = slot.material if slot is not None else None
            if not materials.is_phong_material(mat):
                warnings.append(f"{obj.name}: faces without a Phong material are not exported")
                continue
            if mat.name not in made:
                made[mat.name] = material(mat, warnings)
            picked = slots == slot_index
            count = int(picked.sum()) * 3
            mesh = x3d.Mesh(name=f"{obj.name}", positions=points[picked].reshape(-1, 3),
                            face_sizes=np.full(count // 3, 3, np.int64),
                            corners=np.arange(count, dtype=np.int64),
                            normals=normals[picked].reshape(-1, 3), solid=False)
            shape = x3d.Shape(name=obj.name, geometry=mesh,
                              appearance=x3d.Appearance(material=made[mat.name]))
            groups[tuple(entry["lights"])].children.append(shape)
    doc.root.children.extend(groups[s] for s in sets)
    return doc, sorted(set(warnings))
