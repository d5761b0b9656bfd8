# SPDX-License-Identifier: GPL-3.0-or-later
"""The lights of a scene as one generated node group: "Phong Lights <scene>".

Every light's nodes and drivers live once per scene and light set, in a shader node group
that every Phong material of that light set uses (one node).  Its inputs are the material's
own values, its outputs the model's colour, each term and the shader:

    inputs   Object Color, Specular Color, Exponent, Blinn, Irradiant Color, Normal,
             View Vector, Ambient Object Color, Specular Strength
    outputs  Color, Irradiant, Ambient, Diffuse, Specular, Shader

Inside, in the seeds' model (docs/contract.md, "Several lights"): one Phong Ambient of the
World's ambient light and the Ambient Object Color (the colour the ambient light sees: MTL's
Ka; a material links it from its Object Color unless it has its own), one Phong Surface (the
Normal and View Vector resolved once) and one Phong Surface Rays (what every light reads of
the point), and per light one group of its type, falloff and shadow ray
(``library.rig_light_group``: a Point or Spot light whose ``phong_falloff`` is POWER gets
the i0/d^k one, k driven by ``phong_power_k``; the falloff is chosen when the group is built,
a change relinks, ``lights.signature``), driven by the light without Python (``drivers.py``),
which adds the light's diffuse and specular light to the sums of the lights before it.
Diffuse and Specular are the sums times the Object Color and the Specular Color; Color is
min(irradiant + ambient + Diffuse + Specular, 1), what a Phong Shading per light chained with
Phong Color Add gives (min taken once over non-negative terms) with fewer nodes: Cycles
compiles every node of every material, Eevee expands them again for each of its passes.
With no light: ambient + irradiant (black when both are zero: docs/model.md §No light at
all).

Each model's light groups, spot angle input, name prefix, the settings it reads of a light
and its composition are its entry in ``node_groups/models.py``; ``COMPOSE`` holds one builder
per composition (the seeds' model above is "phong").

In the three.js model (``scene["phong_model"] == "threejs"``, docs/threejs.md; "chain") each
light is one group too (``library.rig_light_group``: MeshPhongMaterial's diffuse
light and its highlight's two sums; Specular Strength 0 is MeshLambertMaterial), which
three.js Rig Material multiplies by the material's colours; the ambient is a three.js Ambient
and the Irradiant Color is three.js's emissive, added as is; Color is min(ambient + emissive
+ Σ lights, 1), what three.js's chain of Phong Color Adds gives.  Blinn is not used there;
the seeds' model does not use Specular Strength (its lights' Specular Strength is theirs).

In the X3D / VRML97 model (``"x3d"``, docs/x3d.md; "phong_light_ambient") each light is one
group (``library.rig_light_group``: intensity and ambient intensity, attenuation
1/max(a0 + a1·d + a2·d², 1) within a radius, the linear spot ramp, its diffuse, Blinn
specular without the N·L condition, and ambient light); the sums are multiplied by the
Object Color, the Specular Color and the Ambient Object Color (X3D's ambientIntensity ×
diffuseColor), the World's Phong ambient is added as in the seeds' model (an imported X3D
file sets it to 0), and Color is min(irradiant + ambient + diffuse + specular, 1).  Blinn
and Specular Strength are not used there.

The number of drivers depends on the lights (about 12 per light), not on the objects.  A
light's location and axis are not driven in the group: drivers on the World write them as
World custom properties that Attribute nodes (View Layer) read (``world_copies.py``), so moving
a light re-evaluates no material (docs/contract.md, "Lights' transforms on the world").

On Blender 5.3+ a group of a model that Eevee's light loop runs (``loop.supports``) also has
the output "Eevee Shader": the loop part (``loop.py``), which does not depend on the lights,
shown by the material's EEVEE Material Output, while Cycles shows "Shader".  Eevee then
compiles nothing of the per-light part, so every light's transform comes from the World
(``compat.view_layer_lookups``).  Not while a view layer of the scene has the Phong term
passes: their AOVs evaluate the per-light part in Eevee too, so the group is then the one of
5.2 (``wants_loop``).

On Blender 5.1+ (``compat.HAS_RAYCAST``), where no view layer has a Phong term pass
(``wants_shadows``), each light's group is its "with Shadow" one, whose Raycast node's shadow
ray (``shadows.py``) darkens its light: Color, Diffuse, Specular and the output "Cycles
Shader" (last: the material's CYCLES Material Output) are shadowed; the Shader is the same
from the groups' Plain sums, without shadows (what Eevee shows where it shows the group:
its Raycast node is screen space only).
"""

from __future__ import annotations

import contextlib
import dataclasses

import bpy

from ...node_groups import library, models
from .. import compat, loader
from . import drivers, ownership, parked_drivers, properties
from . import loop as light_loop
from . import shadows as shadow_rays
from . import world_copies

#: Custom properties of a lights group: the scene it belongs to, its light set and its
#: highlight (``ownership.py``, with the look-ups ``owner``, ``groups_of``, ``find`` and
#: ``highlight_of``).
SCENE_KEY, SET_KEY = ownership.SCENE_KEY, ownership.SET_KEY
HIGHLIGHT_KEY = ownership.HIGHLIGHT_KEY
owner, groups_of, find = ownership.owner, ownership.groups_of, ownership.find
highlight_of = ownership.highlight_of
#: Bump when the layout of the lights group changes.
RIG_VERSION = 12  # 4: lights' transforms from World custom properties (View Layer attributes);
# 5: one Phong Surface and a Phong Light Terms per light instead of a Phong Shading per light;
# 6: a light's i0 from the fourth component of its World copy (its Power: live);
# 7: one group per light, its shadow ray inside (library.rig_light_group): the fewest nodes;
# 8: the seeds' light groups read ℓ (its ray's direction is the light vector) and, on 5.3,
#    draw an i0/(αr² + γ) falloff with r² as one dot product
# 9: the three.js and X3D light groups leaner (ℓ toward the light, the ray's side in one node)
# 10: the seeds' shadow ray's side in one node too (Faceforward);
# 11: before 5.3, a lights group per highlight of its materials (``highlight_for``)
# 12: before 5.3, a three.js or X3D light's group by its constants (``properties.facts_of``);
#     a sun's or spot's axis read as its unit +Z axis (World copy "UNIT_AXIS")
#: Before Blender 5.3 (no Switch node, whose constant condition Blender's inliner folds), a
#: light group of a model that blends the highlights by the material's Blinn computes both
#: highlights and the blend, whatever the Blinn; so a scene's lights group for a light set
#: comes in up to three highlights (``library.HIGHLIGHTS``), and each Phong material uses the
#: one its Blinn asks for: Phong's alone where Blinn is the constant 0, Blinn-Phong's alone
#: where it is the constant 1, the blend otherwise (any value between, or a Blinn that is
#: linked, keyframed or driven).  On 5.3 the Switch does this inside the one group.
HIGHLIGHT_VARIANTS = library.SWITCH_FEATURE not in compat.NODE_FEATURES
#: What a lights group's name adds for a highlight that is not its model's usual one
#: (``usual_highlight``: Blinn 0, the default, before 5.3).
HIGHLIGHT_NAMES = {library.BLEND: " (Phong-Blinn blend)",
                   library.BLINN: " (Blinn-Phong highlights)", library.PHONG: " (Phong highlights)"}
VERSION_KEY = "phong_lights_version"
ALL = "*"
#: The lighting models (``node_groups/models.py``: docs/model.md, docs/threejs.md,
#: docs/x3d.md); a scene's is ``scene[MODEL_KEY]`` (default the seeds'), also stamped on its
#: lights groups.
MODELS = models.NAMES
MODEL_KEY = properties.MODEL_KEY

INPUTS = (  # (name, socket type, default)
    ("Object Color", "NodeSocketColor", (0.8, 0.8, 0.8, 1.0)),
    ("Specular Color", "NodeSocketColor", (1.0, 1.0, 1.0, 1.0)),
    ("Exponent", "NodeSocketFloat", 30.0),
    ("Blinn", "NodeSocketFloat", 0.0),
    ("Irradiant Color", "NodeSocketColor", (0.0, 0.0, 0.0, 1.0)),
    ("Normal", "NodeSocketVector", (0.0, 0.0, 0.0)),
    ("View Vector", "NodeSocketVector", (0.0, 0.0, 0.0)),
    # last, so that the sockets before it keep their identifiers (and links) on upgrade
    ("Ambient Object Color", "NodeSocketColor", (0.8, 0.8, 0.8, 1.0)),
    ("Specular Strength", "NodeSocketFloat", 1.0),  # three.js's specularStrength
)
TERMS = ("Irradiant", "Ambient", "Diffuse", "Specular")
OUTPUTS = (("Color", "NodeSocketColor"),) + tuple((t, "NodeSocketColor") for t in TERMS) + (
    ("Shader", "NodeSocketShader"),)
if compat.HAS_LIGHT_LOOP:  # last: the sockets before it keep their identifiers and links
    OUTPUTS += ((light_loop.EEVEE_SHADER, "NodeSocketShader"),)
if compat.HAS_RAYCAST:  # the Shader with shadow rays, for Cycles (``shadows.py``)
    OUTPUTS += ((shadow_rays.CYCLES_SHADER, "NodeSocketShader"),)
#: The AOVs of the term passes (``recipe.AOVS``, ``phong.add_term_passes``).
PASS_NAMES = ("Phong Color",) + tuple(f"Phong {t}" for t in TERMS)


def wants_term_passes(scene) -> bool:
    """Whether a view layer of *scene* has one of the Phong term passes (AOVs)."""
    return any(aov.name in PASS_NAMES for layer in scene.view_layers for aov in layer.aovs)


def wants_loop(scene) -> bool:
    """Whether *scene*'s lights groups get the loop part: Blender 5.3+, a model the loop
    runs, and no Phong term pass on its view layers (the AOVs would make Eevee evaluate the
    per-light part anyway, at the cost of 5.2's lights group: docs/benchmarks.md, "Eevee's
    light loop")."""
    return light_loop.supports(model_of(scene)) and not wants_term_passes(scene)


def wants_shadows(scene) -> bool:
    """Whether *scene*'s lights groups cast shadow rays (``shadows.py``): Blender 5.1+ (the
    Raycast node) and no Phong term pass on its view layers (their AOV outputs would make
    Eevee evaluate the group's terms, and with them the Raycast nodes)."""
    return shadow_rays.supported() and not wants_term_passes(scene)


model_of = properties.model_of


def highlight_for(model: str, blinn) -> str:
    """The highlight (``library.HIGHLIGHTS``) of the lights group of *model* for a material
    whose Blinn is *blinn* (a number where it is a constant, ``recipe.blinn_constant``; None
    where it is linked or animated): see ``HIGHLIGHT_VARIANTS``."""
    if not HIGHLIGHT_VARIANTS or not models.MODELS[model].blinn:
        return library.BLEND
    return library.PHONG if blinn == 0.0 else library.BLINN if blinn == 1.0 else library.BLEND


def highlights(model: str) -> tuple:
    """The highlights *model*'s lights groups come in on this Blender."""
    if HIGHLIGHT_VARIANTS and models.MODELS[model].blinn:
        return tuple(library.HIGHLIGHTS)
    return (library.BLEND,)


def usual_highlight(model: str) -> str:
    """The highlight of *model*'s lights group for a material at the default Blinn (0): the
    one whose group is named without ``HIGHLIGHT_NAMES``."""
    return highlight_for(model, next(d for n, _t, d in INPUTS if n == "Blinn"))


def set_key(lights, everything: bool) -> str:
    """The key of a light set: "*" when it holds every light of the scene, else the names."""
    return ALL if everything else "\n".join(sorted(o.name for o in lights))


def group_name(scene, lights, key: str, highlight: str | None = None) -> str:
    """The name of *scene*'s lights group for *lights* (key *key*) and *highlight* (default:
    its model's usual one, ``usual_highlight``)."""
    model = model_of(scene)
    name = f"{models.MODELS[model].prefix} Lights {scene.name}"
    if key != ALL:
        name += f" [{', '.join(o.name for o in lights) or 'no light'}]"
    if highlight is not None and highlight != usual_highlight(model):
        name += HIGHLIGHT_NAMES[highlight]
    return name


def ensure(scene, lights, key: str, blends: bool = False, highlight: str | None = None):
    """The lights group of *scene* for *lights* (key *key*) and *highlight* (``highlight_for``;
    default: the model's usual one), created or rebuilt.  *blends*: a Phong material of the
    scene blends (Opacity below 1): Eevee then compiles its group
    (``engine_outputs.eevee_shader``), which so reads at most ``compat.VIEW_LAYER_LOOKUPS``."""
    if highlight is None:
        highlight = usual_highlight(model_of(scene))
    loop = wants_loop(scene)
    lookups = compat.view_layer_lookups(loop and not blends)
    tree = find(scene, key, highlight)
    name = group_name(scene, lights, key, highlight)
    if tree is None:
        tree = bpy.data.node_groups.new(name, "ShaderNodeTree")
        tree[SCENE_KEY] = scene
        tree[SET_KEY] = key
        build(tree, lights, scene.world, model_of(scene), loop, lookups, wants_shadows(scene),
              highlight)
        return tree
    tree = rebuild(tree, lights, scene.world, model_of(scene), loop, lookups,
                   wants_shadows(scene), highlight)
    if not (tree.name == name or tree.name.startswith(name + ".")):  # the scene was renamed
        tree.name = name
    return tree


def tidy_names(scene) -> None:
    """Each lights group of *scene* under its own name where it is free: a group made while
    another (of a highlight no material uses any more, since removed) had it was named
    "<name>.001"."""
    for tree in groups_of(scene):
        key = tree.get(SET_KEY)
        if key is None:
            continue
        lights = [_Named(str(n)) for n in tree.get("phong_lights", ())]
        name = group_name(scene, lights, key, highlight_of(tree))
        if tree.name != name and bpy.data.node_groups.get(name) is None:
            tree.name = name


@dataclasses.dataclass(frozen=True)
class _Named:
    """A light as ``group_name`` reads it: its name (a group's ``phong_lights``)."""

    name: str


def rebuild(tree, lights, world, model=MODELS[0], loop=False, lookups=None, shadows=False,
            highlight=library.BLEND):
    """*tree* rewritten for *lights*; returns the group that now stands for it
    (``rewrite``)."""
    return rewrite(tree, lambda t: build(t, lights, world, model, loop, lookups, shadows,
                                         highlight))


#: Non-empty while groups must be rewritten in place (``rewrite``, ``in_place``).
_IN_PLACE: list = []


@contextlib.contextmanager
def in_place():
    """Inside this block ``rewrite`` edits every group in place, never moving its users to a
    new group: what a depsgraph handler must do where the scene instances objects with Phong
    materials (``sync.on_depsgraph_update``)."""
    _IN_PLACE.append(True)
    try:
        yield
    finally:
        _IN_PLACE.pop()


def rewrite(tree, write):
    """*tree* (a shader node group) rewritten by ``write(tree)``; returns the group that now
    stands for it.

    A group used by many materials is not edited in place (Blender propagates every node
    edit to each material that uses the group: 1,000 materials made a rebuild take 7 s; 26 s
    measured on bpy 5.3.0 for a light added to 1,000 materials, 1.9 s this way): a new group
    is written apart, with the old one's custom properties, takes over the users of the old
    one, and its name.  Not inside ``in_place``: moving the users there crashes Blender (a
    depsgraph handler's relink of a scene that instances objects with Phong materials).
    Either way the group nodes that use it keep their links and values on the sockets of the
    same name (``loader.keeping_links``)."""
    if tree.users <= 1 or _IN_PLACE:
        with loader.keeping_links(tree):
            write(tree)
        return tree
    fresh = bpy.data.node_groups.new(tree.name + " (new)", "ShaderNodeTree")
    for key in tree.keys():
        fresh[key] = tree[key]
    write(fresh)
    name = tree.name
    with loader.keeping_links(tree, fresh):
        tree.user_remap(fresh)
    bpy.data.node_groups.remove(tree)
    fresh.name = name
    return fresh


def build(tree, lights, world, model=MODELS[0], loop=False, lookups=None,
          shadows=False, highlight=library.BLEND) -> None:
    """(Re)write *tree* for *lights* (supported light objects) and *world* in *model* with
    *highlight* (``highlight_for``: the blend by Blinn, or one highlight alone);
    *loop*: with the loop part (Blender 5.3+: ``loop.py``), ignored where Eevee's light loop
    does not run *model*; *lookups*: the View Layer lookups it may hold (default
    ``compat.view_layer_lookups(loop)``); *shadows*: with a shadow ray per light
    (``shadows.py``; ignored before 5.1): Color, Diffuse, Specular and the Cycles Shader
    are shadowed, the Shader (what Eevee shows where it shows the group) is not."""
    loop = loop and light_loop.supports(model)
    shadows = shadows and shadow_rays.supported()
    if parked_drivers.PARKED_KEY in tree.keys():  # written afresh: every driver live
        del tree[parked_drivers.PARKED_KEY]
    _interface(tree)
    if lookups is None:
        lookups = compat.view_layer_lookups(loop)
    budget = [world, lookups, compat.VIEW_LAYER_LOOKUPS]
    COMPOSE[models.MODELS[model].composition](tree, lights, world, budget, model, loop, shadows,
                                              highlight)


def _build_lean(tree, lights, world, budget, model, loop=False, shadows=False,
                highlight=library.BLEND) -> None:
    """Every composition (``models.COMPOSITIONS``: the seeds' "phong", docs/contract.md
    "Several lights"; three.js's "chain"; X3D's "phong_light_ambient"): per light one group
    of its type, falloff and shadow ray (``library.rig_light_group``: the fewest exact nodes
    a light costs, benchmarks/README.md), each adding its light to the sums of the lights
    before it (*highlight*: each light's group draws the blend, or that highlight alone,
    ``highlight_for``); Diffuse = Σ diffuse light ⊗ Object Color, Specular = Σ specular light ⊗
    Specular Color (three.js: its ``rig_material`` applies the material's colours), Ambient =
    the World's ambient (+ X3D: Σ the lights' own ambient light ⊗ Ambient Object Color),
    Color = min(Irradiant + Ambient + Diffuse + Specular, 1).  With shadow rays each light
    also adds to the Plain sums, its light without its shadow: the Shader (what Eevee shows
    before 5.3)."""
    group_in, group_out, out_x = _start(tree, lights, shadows)
    surface = _group_node(tree, "Phong Surface", "surface", (-600.0, 520.0))
    for name in ("Normal", "View Vector"):
        tree.links.new(group_in.outputs[name], surface.inputs[name])
    rays = _group_node(tree, "Phong Surface Rays", "surface rays", (-300.0, 820.0))
    for name in ("Normal", "View Vector"):
        tree.links.new(surface.outputs[name], rays.inputs[name])
    shared = shadow_rays.surface(tree, (-1800.0, 900.0)) if shadows else None
    shared_inputs = {"Normal": surface.outputs["Normal"],
                     "View Vector": surface.outputs["View Vector"],
                     "Reflected View": rays.outputs["Reflected View"],
                     "Light Gate Normal": rays.outputs["Light Gate Normal"],
                     "Surface Position": shared["P"] if shared else rays.outputs["Position"],
                     "Exponent": group_in.outputs["Exponent"],
                     "Blinn": group_in.outputs["Blinn"],
                     "Specular Strength": group_in.outputs["Specular Strength"]}
    if shared:
        shared_inputs.update({"True Normal": shared["Ng"], "Ray Lift": shared["lift"]})
    entry = models.MODELS[model]
    sums = {}
    lambert = []  # n·2⁻⁷ (three.js's lights: library.LAMBERT_SCALE), made for the first

    def lambert_normal():
        if not lambert:
            lambert.append(_vector_node(tree, "MULTIPLY", "surface:lambert normal",
                                        (-300.0, 1000.0), surface.outputs["Normal"],
                                        (library.LAMBERT_SCALE,) * 3))
        return lambert[0]

    for index, obj in enumerate(lights):
        light = obj.data
        falloff = "POWER" if _is_power(light, model) else "QUADRATIC"
        name = library.rig_light_group(model, models.drawn_as(light.type), falloff, shadows,
                                       highlight, properties.facts_of(light, model))
        node = _light_node(tree, obj, (-600.0, -520.0 * index), model, budget, name)
        for socket, source in (*shared_inputs.items(), *sums.items()):
            if socket in node.inputs and not (socket == "Specular Strength"
                                              and entry.rig_material is None):
                tree.links.new(source, node.inputs[socket])  # the seeds' is the light's
        if "Lambert Normal" in node.inputs:
            tree.links.new(lambert_normal(), node.inputs["Lambert Normal"])
        drivers.light_color(node.inputs["Light Color"], light)
        for attr, socket in (("diffuse", "Diffuse Strength"), ("specular", "Specular Strength"),
                             ("power_k", "Falloff Exponent")):
            if socket in node.inputs and not node.inputs[socket].is_linked:  # the seeds'
                drivers.prop(node.inputs[socket], None, "LIGHT", light,
                             f'["{properties.LIGHT_KEYS[attr][0]}"]')
        if shadows:  # Cast Shadow off: no hit counts
            drivers.prop(node.inputs["Cast Shadow"], None, "LIGHT", light, "use_shadow")
        sums = {socket.name: socket for socket in node.outputs}
    world_ambient = _group_node(tree, entry.ambient[0], "ambient", (-300.0, 520.0))
    tree.links.new(group_in.outputs["Ambient Object Color"],
                   world_ambient.inputs[entry.ambient[1]])
    _drive_ambient(world_ambient, world)
    ambient = world_ambient.outputs["Color"]
    if "Ambient Sum" in sums:  # the lights' own ambient light (X3D)
        lights_ambient = _vector_node(tree, "MULTIPLY", "ambient:color", (180.0, 520.0),
                                      sums["Ambient Sum"],
                                      group_in.outputs["Ambient Object Color"])
        ambient = _vector_node(tree, "ADD", "ambient:sum", (360.0, 520.0), ambient,
                               lights_ambient)
    base = (group_in.outputs["Irradiant Color"], ambient)

    def colour(prefix, link):
        totals = []
        material = None
        if entry.rig_material is not None and sums:
            material = _group_node(tree, entry.rig_material, f"{prefix.lower()}material",
                                   (180.0 * len(lights), -200.0 - 400.0 * bool(prefix)))
            for name in ("Diffuse Sum", "Specular Sum", "Fresnel Sum"):
                tree.links.new(sums[prefix + name], material.inputs[name])
            for source, target in THREEJS_SHADING.items():
                if target in material.inputs:
                    tree.links.new(group_in.outputs[source], material.inputs[target])
        for term, color in (("Diffuse", "Object Color"), ("Specular", "Specular Color")):
            total = sums.get(f"{prefix}{term} Sum")
            if material is not None:
                total = material.outputs[term]
            elif total is not None:
                total = _vector_node(tree, "MULTIPLY", f"{prefix.lower()}{term.lower()}:color",
                                     (180.0 * len(lights), -200.0 - 160.0 * len(totals)),
                                     total, group_in.outputs[color])
            if link and total is None:  # no light
                group_out.inputs[term].default_value = (0.0, 0.0, 0.0, 1.0)
            elif link:
                tree.links.new(total, group_out.inputs[term])
            totals.append(total)
        return _color_sum(tree, base, totals, prefix.lower())

    color = colour("", True)
    tree.links.new(color, group_out.inputs["Color"])
    tree.links.new(group_in.outputs["Irradiant Color"], group_out.inputs["Irradiant"])
    tree.links.new(ambient, group_out.inputs["Ambient"])
    _shaders(tree, color, group_out, out_x, shadows and (lambda: colour("Plain ", False)))
    if loop:  # the X3D lights' own ambient light comes from the loop (X3D Loop Light)
        light_loop.build(tree, model, group_in, group_out,
                         group_in.outputs["Irradiant Color"], world_ambient.outputs["Color"],
                         surface, shadows)
    _stamp(tree, lights, model, highlight)


def _color_sum(tree, base, totals, prefix=""):
    """min(*base*[0] + *base*[1] + the *totals* (None: no light), 1): the seeds' and X3D's
    Color."""
    color = _vector_node(tree, "ADD", f"{prefix}color:base", (0.0, 300.0), *base)
    for index, total in enumerate(t for t in totals if t is not None):
        color = _vector_node(tree, "ADD", f"{prefix}color:{index}",
                             (180.0 * (index + 1), 300.0), color, total)
    return _vector_node(tree, "MINIMUM", f"{prefix}color", (180.0 * 3, 300.0), color,
                        (1.0, 1.0, 1.0))


def _shaders(tree, color, group_out, out_x, plain=None) -> None:
    """The Shader outputs: an emission of *color*; where the group casts shadow rays
    (*plain*: a callable that writes the colour without them) the Cycles Shader is that
    emission and the Shader (what Eevee shows) the emission of the plain colour."""
    cycles = group_out.inputs.get(shadow_rays.CYCLES_SHADER)
    if not plain:
        emission = _emission(tree, color, group_out, out_x)
        if cycles is not None:  # the same shader
            tree.links.new(emission.outputs["Emission"], cycles)
        return
    _emission(tree, plain(), group_out, out_x)
    _emission(tree, color, group_out, out_x, shadow_rays.CYCLES_SHADER)


def _stamp(tree, lights, model, highlight=library.BLEND) -> None:
    tree[VERSION_KEY] = RIG_VERSION
    tree[MODEL_KEY] = model
    tree[HIGHLIGHT_KEY] = highlight
    tree["phong_lights"] = [obj.name for obj in lights]
    tree[light_loop.LOOP_KEY] = tree.get(light_loop.LOOP_KEY) or ""


def _start(tree, lights, shadows=False):
    """Clear *tree*; returns (group input, group output, x of the sums' end)."""
    if tree.animation_data is not None:
        tree.animation_data_clear()
    tree.nodes.clear()
    tree[shadow_rays.KEY] = int(bool(shadows) and shadow_rays.supported())
    world_copies.clear_listed(tree)
    tree[light_loop.LOOP_KEY] = ""
    group_in = tree.nodes.new("NodeGroupInput")
    group_in.location = (-900.0, 0.0)
    group_out = tree.nodes.new("NodeGroupOutput")
    out_x = 500.0 + 180.0 * max(len(lights), 1)
    group_out.location = (out_x + 250.0, 0.0)
    return group_in, group_out, out_x


#: three.js model: the input of three.js Rig Material fed by each input of the lights group.
THREEJS_SHADING = {"Object Color": "Diffuse Color", "Specular Color": "Specular Color",
                   "Exponent": "Shininess", "Specular Strength": "Specular Strength"}


#: composition (``models.COMPOSITIONS``) -> its builder(tree, lights, world, budget, model,
#: loop, shadows, highlight).
COMPOSE = {"phong": _build_lean, "chain": _build_lean, "phong_light_ambient": _build_lean}


def _emission(tree, color, group_out, out_x, output="Shader"):
    """An Emission of *color* into *output*; returns it."""
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.name = "emission" if output == "Shader" else "emission:cycles"
    emission.location = (out_x, 300.0 if output == "Shader" else 100.0)
    emission.inputs["Strength"].default_value = 1.0
    tree.links.new(color, emission.inputs["Color"])
    tree.links.new(emission.outputs["Emission"], group_out.inputs[output])
    return emission


def _interface(tree) -> None:
    """The interface of INPUTS / OUTPUTS.  The sockets *tree* has keep their identifiers (so
    the group nodes in materials keep their links on the inputs they mean); a socket not wanted
    goes (a group of 5.3 opened by an earlier Blender: its Eevee Shader); a missing one is
    added at its place (an older rig)."""
    want = ([("OUTPUT", n, t) for n, t in OUTPUTS] + [("INPUT", n, t) for n, t, _d in INPUTS])
    while True:  # one at a time: a removal may move the other items
        seen, doomed = set(), None
        for item in _sockets(tree):
            key = (item.in_out, item.name, item.socket_type)
            if key not in want or key in seen:
                doomed = item
                break
            seen.add(key)
        if doomed is None:
            break
        tree.interface.remove(doomed)
    have = [(i.in_out, i.name, i.socket_type) for i in _sockets(tree)]
    if have != want:
        _append_sockets(tree, have, want)


def _sockets(tree) -> list:
    return [i for i in tree.interface.items_tree if i.item_type == "SOCKET"]


def _append_sockets(tree, have, want) -> None:
    """Add the sockets of INPUTS / OUTPUTS that *tree* lacks, and put each at its place."""
    defaults = {name: default for name, _type, default in INPUTS}
    for in_out, name, socket_type in want:
        if (in_out, name, socket_type) in have:
            continue
        item = tree.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
        if name in defaults:
            item.default_value = defaults[name]
        if name in ("Blinn", "Specular Strength"):
            item.min_value, item.max_value = 0.0, 1.0
    for position, key in enumerate(want):
        items = _sockets(tree)
        item = next(i for i in items if (i.in_out, i.name, i.socket_type) == key)
        if items.index(item) != position:
            tree.interface.move(item, position)


def _group_node(tree, group_name, name, location):
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree, _status = loader.ensure_group(group_name)
    node.name = node.label = name
    node.location = location
    node.width = 200.0
    return node


def _light_node(tree, obj, location, model, budget=(None, 0, 0), group=None):
    """The light group of *obj* in *model*, driven by the light; its transform from the
    World (*budget*: [world, View Layer lookups left, those of them Eevee may compile left],
    spent here) or by drivers.  An Area light is drawn by the model's spot group
    (``models.drawn_as``): a hemisphere around its -Z axis with the model's ``area``
    settings."""
    light = obj.data
    kind = models.drawn_as(light.type)
    properties.ensure_light_props(light)
    light_loop.write_parameters(light)  # what the light loop reads of it (5.3+; else nothing)
    spec = models.MODELS[model]
    node = _group_node(tree, group or spec.light_groups[kind], f"light:{obj.name}", location)
    inputs = node.inputs
    keys = {attr: f'["{key}"]' for attr, (key, _default) in properties.LIGHT_KEYS.items()}
    kinds = [name for name, types in (("LOCATION", ("POINT", "SPOT")),
                                      ("UNIT_AXIS", ("SUN", "SPOT"))) if kind in types]
    world = budget[0]
    from_world = world is not None and world.library is None and budget[1] >= len(kinds)
    targets = {attr: target for attr, target in properties.model_settings(model, light)}
    i0_from_world = False
    if from_world:
        budget[1] -= len(kinds)
        eevee = len(budget) < 3 or budget[2] >= len(kinds)
        if len(budget) >= 3 and eevee:
            budget[2] -= len(kinds)
        for row, name in enumerate(kinds):
            socket = inputs[world_copies.TRANSFORM_SOCKETS[name]]
            listed = world_copies.WORLD_KEYS if eevee else world_copies.LOOP_WORLD_KEYS
            carries = world_copies.carries_intensity(obj, name) and targets.get("intensity")
            world_copies.read(tree, world, obj, name, socket,
                              (location[0] - 300.0, location[1] - 160.0 * row), listed,
                              intensity=inputs[targets["intensity"]] if carries else None)
            i0_from_world = i0_from_world or bool(carries)
    if kind in ("POINT", "SPOT"):
        if not from_world:
            drivers.world_location(inputs["Position"], obj)
        if _is_power(light, model):  # i0 here; _power_falloff divides by d^k
            for name, value in (("Quadratic", 0.0), ("Linear", 0.0), ("Constant", 1.0)):
                if name in inputs:  # (the seeds' lights group's light has its own i0/d^k)
                    inputs[name].default_value = value
    if kind in ("SUN", "SPOT") and not from_world:
        drivers.world_unit_z(inputs[world_copies.TRANSFORM_SOCKETS["UNIT_AXIS"]], obj)
    if light.type == "SPOT":
        drivers.prop(inputs[spec.spot_angle], None, "LIGHT", light, "spot_size", scale=0.5)
    elif light.type == "AREA":
        inputs[spec.spot_angle].default_value = models.AREA_HALF_ANGLE
        spot_inputs = {attr: target for attr, _types, _when, target in spec.settings}
        for attr, value in spec.area:
            if spot_inputs.get(attr) is not None:
                inputs[spot_inputs[attr]].default_value = value
    for attr, target in targets.items():
        if target is None or (attr == "intensity" and i0_from_world):
            continue
        if attr == "intensity":  # its own i0, or its Power's: one live driver
            drivers.light_intensity(inputs[target], light, keys[attr],
                                    f'["{properties.FROM_POWER_KEY}"]',
                                    properties.power_scale(light))
        else:
            drivers.prop(inputs[target], None, "LIGHT", light, keys[attr])
    return node


def _is_power(light, model) -> bool:
    """Whether *light* falls off as i0/d^k in its lights group (Point and Spot of a model
    that reads the falloff: the seeds')."""
    return (models.MODELS[model].power_falloff
            and models.drawn_as(light.type) in ("POINT", "SPOT")
            and properties.falloff_of(light) == "POWER")


def _drive_ambient(node, world) -> None:
    """The Phong Ambient node's light: the World's Phong ambient intensity and colour."""
    if world is None:
        node.inputs["Intensity"].default_value = properties.NO_WORLD_AMBIENT
        node.inputs["Light Color"].default_value = (*properties.AMBIENT_COLOR[1], 1.0)
        return
    properties.ensure_world_props(world)
    drivers.prop(node.inputs["Intensity"], None, "WORLD", world,
                 f'["{properties.AMBIENT_INTENSITY[0]}"]')
    drivers.color(node.inputs["Light Color"], "WORLD", world,
                  f'["{properties.AMBIENT_COLOR[0]}"]')


def _vector_node(tree, operation, name, location, a, b):
    """A Vector Math node *operation* of *a* and *b* (sockets, or a constant vector for *b*);
    returns its Vector output."""
    node = tree.nodes.new("ShaderNodeVectorMath")
    node.name = node.label = name
    node.operation = operation
    node.location = location
    tree.links.new(a, compat.input_socket(node, "Vector"))
    if isinstance(b, tuple):
        compat.input_socket(node, "Vector_001").default_value = b
    else:
        tree.links.new(b, compat.input_socket(node, "Vector_001"))
    return node.outputs["Vector"]
