# SPDX-License-Identifier: GPL-3.0-or-later
"""Shadows: each light's visibility at the shaded point, per engine and release.

The model with shadows is "Phong plus shadow rays": each light's diffuse and specular terms
times its visibility V, 1 unless the segment from the shaded point P to a point or spot
light's position (a sun: the ray from P toward the sun, opposite to its direction) meets a
shadow-casting object, the receiver itself included, then 0.  The ambient and irradiant
light are not shadowed, nor an X3D light's own ambient.  Hard shadows from the light's centre:
a light's Radius / Angle does not soften them.  A light whose Blender **Cast Shadow**
(``light.use_shadow``) is off casts none; the switch is read by a driver (Blender's own
simple expression: no Python), so toggling it renders as a moved light does.

Cycles (Blender 5.1+, ``compat.HAS_RAYCAST``): per light a Raycast node, inside the light's
group of the lights group (``library.rig_light_group``, "with Shadow": a hit adds 10³⁰ to
the light's falloff denominator), from P moved along the true normal, to the light's side of
the surface, by ``OFFSET`` · (1 + max |P|) (from P itself the node skips only the shading
triangle: acne along the diagonals of a finely split floor; 1e-3 lets light leak), toward
the light with Length 1 in units of the direction (the direction is the segment itself;
lights are never hit), or a sun's direction with Length ``library.SUN_RAY_LENGTH``; what
every light's ray shares is written here once per lights group (:func:`surface`).  The node honours an object's Ray
Visibility ▸ Ray Cast on 5.3 (``visible_raycast``; 5.2: only an object with every ray
visibility off is skipped), not Ray Visibility ▸ Shadow (``visible_shadow``) nor Light
Linking's shadow blockers; a transparent (Opacity below 1) caster blocks the light.

Ray Visibility ▸ Shadow in Cycles (5.3, :func:`follow_shadow`): in a scene whose lights
groups cast shadow rays, turning an object's Shadow off turns its Ray Cast off too (noted on
the object, ``OWN_RAYCAST`` = 1), turning Shadow on again brings Ray Cast back; a Ray Cast
turned off by hand while Shadow is on is left as it is (the object then casts no Phong shadow
in Cycles but does in Eevee).  The depsgraph handler :func:`follow_shadow_visibility` does
it for the active object, and the selected ones with it (where the Object properties edit
it); Apply, Relink and loading a file (:func:`follow_on_load`) for every object of the
scene.  Once the scene casts no shadow rays (Restore Original Materials of its last Phong
objects, Relink with a term pass) every Ray Cast turned off here
comes back (:func:`give_back_raycast`).

Eevee never evaluates a Raycast node (its node is screen space only): a lights group with
shadows shows them through its output "Cycles Shader" (the material's Material Output of
target CYCLES), and Eevee the group's Shader without shadows, or on 5.3 the light loop
(``loop.py``).  A group gets shadows where no Phong term pass is on a view layer of its scene
(the AOV outputs would make Eevee evaluate the group's terms: ``rig.wants_shadows``).
"""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from ...node_groups import models
from .. import compat
from . import ownership

#: Custom property of a lights group built with shadow rays (1) or without (0).
KEY = "phong_lights_shadows"
#: The output of a lights group that Cycles shows (the Shader with shadows).
CYCLES_SHADER = "Cycles Shader"
#: The ray's origin moves this far along the true normal, times 1 + max |P| (measured: no
#: acne on a 40 × 40 floor at every scene scale tried; 1e-3 leaks light).
OFFSET = 1.0e-5
#: Names of the nodes written here (under their light's name).
PREFIX = "shadow:"


#: Object custom property: 1 while the object's Ray Cast is off because its Shadow is
#: (:func:`follow_shadow`), 0 once given back.
OWN_RAYCAST = "phong_raycast_own"


def supported() -> bool:
    """Whether this Blender casts the shadow rays (Cycles' Raycast node: 5.1+)."""
    return compat.HAS_RAYCAST


def notes(model: str, rays: bool, loop: bool) -> list:
    """What the light panel says of shadows in a scene of *model* whose lights groups cast
    shadow rays (*rays*: ``rig.wants_shadows``) with or without Eevee's light loop (*loop*:
    ``rig.wants_loop``)."""
    if not supported():
        return ["Phong shadows need Blender 5.2+ (Cycles) or 5.3+ (Eevee)"]
    if not rays:
        return ["No Phong shadows while a Phong term pass is on a view layer"]
    lines = ["Phong shadows: hard, from the light's centre (Radius ignored)"]
    if not loop:
        entry = models.get(model)
        why = (f"the {entry.label} model" if entry.loop is None else "Blender before 5.3")
        lines.append(f"Phong shadows in Cycles only ({why}): Eevee shows none")
    lines.append("Cycles: an object casts while its Ray Visibility ▸ Shadow (and Ray Cast) "
                 "is on" if compat.RAYCAST_VISIBILITY else
                 "Cycles 5.2: every object casts unless all its ray visibility is off "
                 "(Ray Visibility ▸ Shadow not read)")
    return lines


def material_notes(shading: str, blends: bool, rays: bool, loop: bool) -> list:
    """What the material panel says of a Phong material's shadows: in *shading* (PIXEL, or
    Per Vertex / Per Face), blending (*blends*: Opacity below 1, an opacity map), in a scene
    with shadow rays (*rays*) and the light loop (*loop*).  Eevee shows the loop's shadows
    only where it shows the loop (``engine_outputs.eevee_shader``); the light panel says the
    rest."""
    if not supported() or not rays:
        return []
    if shading != "PIXEL":
        return ["Per Vertex / Per Face: no Phong shadows (Cycles nor Eevee)"]
    if blends and loop:
        return ["Opacity below 1: Phong shadows in Cycles only (Eevee shows none)"]
    return []


def blocker_note(obj) -> str | None:
    """What the light panel says of the light object *obj*'s Light Linking shadow blockers
    in a scene with shadow rays: Cycles' Raycast node does not read them."""
    linking = getattr(obj, "light_linking", None)
    if linking is None or getattr(linking, "blocker_collection", None) is None:
        return None
    eevee = ", Eevee does" if compat.HAS_LIGHT_LOOP else ""
    return f"Cycles' Phong shadows ignore its shadow blockers (Light Linking){eevee}"


def _raycast_pending(obj) -> bool:
    """Whether *obj*'s Ray Cast is not yet where its Shadow puts it (:func:`follow_shadow`)."""
    ray = getattr(obj, compat.RAYCAST_VISIBILITY)
    if obj.visible_shadow:
        return not ray and obj.get(OWN_RAYCAST) == 1
    return ray


def follow_shadow(obj) -> bool:
    """Ray Cast after Shadow on the object *obj* (5.3; Cycles' Raycast node reads only Ray
    Cast): Shadow off turns Ray Cast off (``OWN_RAYCAST`` = 1), Shadow on gives back a Ray
    Cast turned off here (``OWN_RAYCAST`` = 0; no ID property is removed: safe in a
    depsgraph handler).  Returns whether it changed anything."""
    attr = compat.RAYCAST_VISIBILITY
    if attr is None or obj.library is not None or not hasattr(obj, attr) \
            or not _raycast_pending(obj):
        return False
    if obj.visible_shadow:
        setattr(obj, attr, True)
        obj[OWN_RAYCAST] = 0
    else:
        if obj.get(OWN_RAYCAST) != 1:
            obj[OWN_RAYCAST] = 1
        setattr(obj, attr, False)
    return True


def follow_scene(scene) -> int:
    """:func:`follow_shadow` on every object of *scene* (Apply, Relink); returns how many
    changed."""
    if compat.RAYCAST_VISIBILITY is None:
        return 0
    return sum(follow_shadow(obj) for obj in scene.objects)


def give_back_raycast(scene, remove: bool = True) -> int:
    """Where *scene* casts no shadow rays any more (no Phong material left, a term pass):
    every object's Ray Cast as it was before :func:`follow_shadow` turned it off; *remove*:
    and the note (``OWN_RAYCAST``) removed (not inside a depsgraph handler).  Returns how
    many objects got Ray Cast back."""
    attr = compat.RAYCAST_VISIBILITY
    back = 0
    if attr is None:  # nothing was turned off before 5.3
        return back
    for obj in scene.objects:
        own = obj.get(OWN_RAYCAST)
        if own is None or obj.library is not None:
            continue
        if own == 1 and hasattr(obj, attr):
            setattr(obj, attr, True)
            back += 1
        if remove:
            del obj[OWN_RAYCAST]
        elif own != 0:
            obj[OWN_RAYCAST] = 0
    return back


@persistent
def follow_shadow_visibility(scene, depsgraph=None) -> None:
    """After an object edit: the active object's Ray Cast after its Shadow
    (:func:`follow_shadow`), in a scene whose lights groups cast shadow rays, and then the
    selected objects' (Alt+click).  A light drag costs one look at the active object (no walk
    of ``depsgraph.updates`` nor of the selection)."""
    if depsgraph is None or scene is None or compat.RAYCAST_VISIBILITY is None \
            or not depsgraph.id_type_updated("OBJECT"):
        return
    objects = depsgraph.view_layer.objects
    active = objects.active
    if active is None or active.library is not None or not _raycast_pending(active) \
            or not casts_rays(scene):
        return
    follow_shadow(active)
    for obj in objects.selected:  # Alt+click edits every selected object with the active
        follow_shadow(obj)


@persistent
def follow_on_load(*_args) -> None:
    """After loading a file: :func:`follow_scene` in each of its scenes whose lights groups
    cast shadow rays (a Shadow turned off in a Blender without this mirror, or by a script)."""
    if compat.RAYCAST_VISIBILITY is None:
        return
    for scene in bpy.data.scenes:
        if scene.library is None and casts_rays(scene):
            follow_scene(scene)


def casts_rays(scene) -> bool:
    """Whether a lights group of *scene* casts shadow rays."""
    return any(has_shadows(tree) for tree in ownership.groups_of(scene))


def has_shadows(tree) -> bool:
    """Whether the lights group *tree* was built with shadow rays."""
    return tree is not None and compat.HAS_RAYCAST and bool(tree.get(KEY))


def _node(tree, kind, name, location, operation=None):
    """A new node labelled ``PREFIX + name``; its name stays Blender's: naming a node walks
    every ID of the file (``BKE_animdata_fix_paths_rename_all``: 6 ms a node at 30,000 IDs),
    and nothing looks these nodes up by name."""
    node = tree.nodes.new(kind)
    node.label = PREFIX + name
    node.location = location
    if operation is not None:
        node.operation = operation
    return node


def _vector(tree, operation, name, location, a, b=None, scale=None, c=None):
    node = _node(tree, "ShaderNodeVectorMath", name, location, operation)
    tree.links.new(a, compat.input_socket(node, "Vector"))
    if b is not None:  # a float socket links as (b, b, b)
        tree.links.new(b, compat.input_socket(node, "Vector_001"))
    if c is not None:
        tree.links.new(c, compat.input_socket(node, "Vector_002"))
    if scale is not None:
        tree.links.new(scale, compat.input_socket(node, "Scale"))
    return compat.output_socket(node, "Value" if operation == "DOT_PRODUCT" else "Vector")


def _math(tree, operation, name, location, a, b=None, c=None):
    node = _node(tree, "ShaderNodeMath", name, location, operation)
    for key, source in (("Value", a), ("Value_001", b), ("Value_002", c)):
        if source is None:
            continue
        if isinstance(source, float):
            compat.input_socket(node, key).default_value = source
        else:
            tree.links.new(source, compat.input_socket(node, key))
    return node


def surface(tree, location) -> dict:
    """The shaded point's nodes every light's ray shares: {"P": Position, "Ng": True Normal,
    "offset": OFFSET · (1 + max |P|), "lift": offset · Ng}."""
    x, y = location
    geometry = _node(tree, "ShaderNodeNewGeometry", "geometry", (x, y))
    position = compat.output_socket(geometry, "Position")
    absolute = _vector(tree, "ABSOLUTE", "abs", (x + 180.0, y), position)
    split = _node(tree, "ShaderNodeSeparateXYZ", "xyz", (x + 360.0, y))
    tree.links.new(absolute, compat.input_socket(split, "Vector"))
    top = _math(tree, "MAXIMUM", "max xy", (x + 540.0, y), compat.output_socket(split, "X"),
                compat.output_socket(split, "Y"))
    top = _math(tree, "MAXIMUM", "max", (x + 720.0, y), compat.output_socket(top, "Value"),
                compat.output_socket(split, "Z"))
    offset = _math(tree, "MULTIPLY_ADD", "offset", (x + 900.0, y),
                   compat.output_socket(top, "Value"), OFFSET, OFFSET)
    normal = compat.output_socket(geometry, "True Normal")
    offset = compat.output_socket(offset, "Value")
    lift = _vector(tree, "SCALE", "lift", (x + 1080.0, y), normal, scale=offset)
    return {"P": position, "Ng": normal, "offset": offset, "lift": lift}
