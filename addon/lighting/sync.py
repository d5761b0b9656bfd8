# SPDX-License-Identifier: GPL-3.0-or-later
"""Keep a scene's Phong materials in step with its lights.

:class:`Sync` does the work of Apply Phong Material and Relink Phong Lights: it builds the
scene's lights groups (one per light set), converts source materials to Phong materials
(one per source material and light set) and points every Phong material at the group of
its objects' light set.  :func:`on_depsgraph_update` runs it after a change to which lights
exist, their types, visibility or Light Linking, so lights follow without a click; when
nothing of that changed it costs one fingerprint of the lights (0.14 ms at 16 lights), and
an update that only moves objects (a light drag) a check of the lights' names
(``only_moved``).
"""

from __future__ import annotations

import contextlib

import bpy
from bpy.app.handlers import persistent

from .. import compat, loader
from . import lights as lights_mod
from . import loop as light_loop
from . import engine_outputs, opacity, recipe, rig, shadows, world_copies, writer
from . import sources as source_materials


#: The name of a template made for textured sources only (``Sync.convert``; removed at the
#: end of the run).
SCRATCH = "Phong template (temporary)"


class Sync:
    """One run over a scene: its lights read once, each group and material built once."""

    def __init__(self, scene, view_layer=None):
        self.scene = scene
        self.model = rig.model_of(scene)
        self.lights, self.unsupported = lights_mod.scene_lights(scene, view_layer)
        self.rules = [lights_mod.receivers(obj) for obj in self.lights]
        self.linked = any(rule is not None for rule in self.rules)
        self.groups: dict = {}
        self.templates: dict = {}
        self.index = {}
        # name -> material, once: bpy.data.materials.get is a linear search (0.5 ms at
        # 6,000 materials), and every Phong material names its source
        self.names = {m.name: m for m in bpy.data.materials}
        self.scratch: list = []  # templates made for textured sources, removed at the end
        self.blends = False  # a Phong material blends: Eevee compiles the lights groups
        for material in recipe.phong_materials():
            self.index.setdefault((self._origin(material), recipe.lights_key(material)),
                                  material)
            self.blends = self.blends or recipe.blends(material)
        engine_outputs.STALE.discard(scene.as_pointer())
        self.changed: set = set()
        #: (source material name, its inputs) whose ambient colour read a linked input's
        #: own value (``sources.ambient_terms``)
        self.ambient_linked: list = []

    # -- light sets and their groups ------------------------------------------------
    def light_set(self, obj):
        """(key, lights) of the lights that reach *obj*."""
        if not self.linked:
            return rig.ALL, self.lights
        reach = lights_mod.light_set(obj, self.lights, self.rules)
        return rig.set_key(reach, len(reach) == len(self.lights)), reach

    def group(self, key, reach, highlight=None):
        """The lights group of the light set *key* (its lights *reach*) with *highlight*
        (``rig.highlight_for``; default the model's usual one: a new material's, Blinn 0),
        made or rebuilt once a run."""
        if highlight is None:
            highlight = rig.usual_highlight(self.model)
        if (key, highlight) not in self.groups:
            self.groups[(key, highlight)] = rig.ensure(self.scene, reach, key, self.blends,
                                                       highlight)
        return self.groups[(key, highlight)]

    def highlight(self, material) -> str:
        """The highlight of the lights group *material* wants (``rig.highlight_for``)."""
        return rig.highlight_for(self.model, recipe.blinn_constant(material))

    # -- materials --------------------------------------------------------------------
    def _origin(self, material):
        source = source_materials.source_of(material, self.names)
        if source is not None:
            return source.as_pointer()
        return ("empty" if material.get(source_materials.EMPTY_SOURCE_KEY)
                else material.as_pointer())

    def _name(self, base, reach, key):
        name = f"Phong {base}"
        if key == rig.ALL:
            return name
        return f"{name} [{', '.join(o.name for o in reach) or 'no light'}]"

    def convert(self, source, key, reach):
        """The Phong material of *source* (a non-Phong material or None) for a light set."""
        origin = source.as_pointer() if source is not None else "empty"
        material = self.index.get((origin, (self.scene.as_pointer(), key)))
        if material is not None:
            return self.rewire(material, key, reach)
        group = self.group(key, reach)
        base = source.name if source is not None else "Material"
        textured = source_materials.base_color_link(source) is not None
        ambient = source_materials.ambient_terms(source)
        # one template per light set and ambient layer (Ka = Kd × scale + offset, or Kd): a
        # copy has the layer's node named and linked, so only its values are written, and
        # quietly (a node named, a link made or a value assigned walks every node tree of
        # the file: Apply at 10,000 Principled materials took 140 s with two values
        # assigned per material)
        layered = not writer.ambient_is_kd(*ambient[0])
        template = self.templates.get((key, layered))
        if template is None and textured:
            template = writer.new_material(SCRATCH, group)
            if layered:
                writer.ambient_layer(template, (0.5, 0.5, 0.5), (0.0, 0.0, 0.0))
            self.templates[(key, layered)] = template
            self.scratch.append(template)
        material = source_materials.from_source(source, self._name(base, reach, key), group,
                                                template=template, linked=self.ambient_linked,
                                                ambient=ambient)
        if template is None:  # untextured: the first of its kind is the template
            self.templates[(key, layered)] = material
        self.index[(origin, (self.scene.as_pointer(), key))] = material
        self.changed.add(material.name)
        return material

    def prepare(self, objects) -> None:
        """Make the Phong materials that ``apply`` will give *objects* ahead, in the order of
        their names.  Blender keeps a file's materials sorted by name, and naming one walks
        that list from its end to the name's place: materials named in the objects' order
        cost up to the number of materials each (Apply at 10,000 objects: 40 of its 62 s),
        named in ascending order each lands at the end."""
        todo = {}
        for obj in objects:
            key, reach = self.light_set(obj)
            for material in [s.material for s in obj.material_slots] or [None]:
                if recipe.is_phong_material(material):
                    continue
                origin = material.as_pointer() if material is not None else "empty"
                if (origin, (self.scene.as_pointer(), key)) in self.index:
                    continue
                base = material.name if material is not None else "Material"
                todo.setdefault((origin, key), (self._name(base, reach, key), material, key,
                                                reach))
        for _name, source, key, reach in sorted(todo.values(), key=lambda t: t[0].casefold()):
            self.convert(source, key, reach)

    def rewire(self, material, key, reach, only_set=False):
        """*material* (a Phong material) for the light set *key* of this scene: itself when it
        fits (or has no set yet), else its variant for that set (a material used in two scenes
        gets one per scene: each scene has its own lights groups).  *only_set*: every user of
        *material* in this scene wants this set, so when its set changed (a light renamed,
        linking edited) the material itself moves to the new set instead of being copied."""
        current = recipe.lights_key(material)
        wanted = (self.scene.as_pointer(), key)
        if current is not None and current != wanted:
            origin = self._origin(material)
            variant = self.index.get((origin, wanted))
            if variant is None and only_set and current[0] == wanted[0]:
                if self.index.get((origin, current)) is material:
                    del self.index[(origin, current)]
                self.index[(origin, wanted)] = material
                base = material.name.split(" [")[0].removeprefix("Phong ")
                if material.name.startswith(f"Phong {base} ["):  # a generated name: follow
                    material.name = self._name(base, reach, key)
            elif variant is None:
                variant = material.copy()
                source = source_materials.source_of(material)
                base = source.name if source is not None else material.name.removeprefix("Phong ")
                compat.rename(variant, self._name(base.split(" [")[0], reach, key))
                self.index[(origin, wanted)] = variant
                material = variant
            else:
                material = variant
        group = self.group(key, reach, self.highlight(material))
        node = material.node_tree.nodes.get(recipe.LIGHTS_NODE)
        if material.name in self.changed and node is not None and node.node_tree is group:
            return material  # made or wired by this run: nothing to check again
        if (source_materials.upgrade(material) or node is None or node.node_tree is not group
                or int(material.get(recipe.MATERIAL_TAG, 0)) < recipe.LAYOUT):
            writer.wire(material, group)
            self.changed.add(material.name)
        elif not engine_outputs.eevee_in_step(material):  # the loop part came or went (5.3+)
            writer.wire(material, group)
            self.changed.add(material.name)
        elif not opacity.opacity_in_step(material):  # its Opacity node written directly
            opacity.apply_opacity(material)
        return material

    # -- objects --------------------------------------------------------------------------
    def apply(self, obj) -> list:
        """Phong materials in every slot of *obj* (a slot is added when it has none)."""
        key, reach = self.light_set(obj)
        if not obj.material_slots:
            obj.data.materials.append(None)
        done = []
        for slot in obj.material_slots:
            material = slot.material
            if recipe.is_phong_material(material):
                new = self.rewire(material, key, reach)
            else:
                new = self.convert(material, key, reach)
            if slot.material is not new:
                slot.material = new
            done.append(new)
        return done

    def relink(self, objects) -> int:
        """Every Phong material on *objects* pointed at its light set's group (groups
        rebuilt first); returns how many objects hold Phong materials."""
        uses = []
        sets: dict = {}  # material pointer -> the light set keys its users want
        for obj in objects:
            if obj.type != "MESH" and not hasattr(obj.data, "materials"):
                continue
            slots = [s for s in obj.material_slots if recipe.is_phong_material(s.material)]
            if not slots:
                continue
            key, reach = self.light_set(obj)
            uses.append((slots, key, reach))
            for slot in slots:
                sets.setdefault(slot.material.as_pointer(), set()).add(key)
        for slots, key, reach in uses:
            for slot in slots:
                only_set = sets.get(slot.material.as_pointer(), {key}) == {key}
                new = self.rewire(slot.material, key, reach, only_set)
                if slot.material is not new:
                    slot.material = new
        return len(uses)

    def rebuild_groups(self) -> None:
        """Rebuild the groups of this scene's light sets that exist (lights changed), and
        remove the scene's groups that no material uses any more."""
        for tree in rig.groups_of(self.scene):
            key, highlight = tree.get(rig.SET_KEY), rig.highlight_of(tree)
            if key == rig.ALL and highlight in rig.highlights(self.model):
                self.groups[(key, highlight)] = rig.ensure(self.scene, self.lights, key,
                                                           self.blends, highlight)
        for tree in rig.groups_of(self.scene):
            if tree.users == 0 and tree not in self.groups.values():
                bpy.data.node_groups.remove(tree)

    def drop_scratch(self) -> None:
        """Remove the templates made for textured sources (never given to an object)."""
        while self.scratch:
            material = self.scratch.pop()
            if material.users == 0:
                bpy.data.materials.remove(material)

    def finish(self, prune: bool = True) -> None:
        """Remove this scene's unused groups; *prune*: and the World properties of lights
        no group reads any more (not inside a depsgraph handler: removing an ID property
        and its drivers there crashed Blender 4.2 in the next handler; Apply and Relink
        prune what the handler left)."""
        for tree in rig.groups_of(self.scene):
            if tree.users == 0:
                bpy.data.node_groups.remove(tree)
        rig.tidy_names(self.scene)
        if prune:
            world_copies.prune()
        if shadows.casts_rays(self.scene):
            shadows.follow_scene(self.scene)  # Cycles 5.3: Ray Cast after Shadow
        else:
            shadows.give_back_raycast(self.scene, remove=prune)
        for follow in AFTER_FINISH:  # an upward call: shading.modes.refresh (addon/__init__.py)
            follow(self.scene)


#: An upward call: callables ``follow(scene)`` run at the end of every Apply / Relink
#: (``Sync.finish``, ``_renew``).  ``addon/__init__.py`` (``connect``) puts the room above
#: that depends on the lights here, ``shading.modes.refresh`` (the Per Vertex / Per Face
#: groups follow the lights), so that lighting imports none of it.
AFTER_FINISH: list = []


@contextlib.contextmanager
def session(scene, view_layer=None, prune: bool = True):
    """One run over *scene* that ends as a relink ends: yields a :class:`Sync` with the
    scene's groups rebuilt; the block makes or binds its Phong materials (Apply, an import,
    a demo scene), and on leaving it every Phong material of the scene's objects is pointed
    at its light set's group (the objects already there too: an imported file's lights may
    reach them), unused groups are removed (*prune*: and the World keys no group reads), the
    World's copies follow (``world_copies.follow``) and the lights are remembered.  An error
    inside the block leaves the end undone: the caller rolls back."""
    sync = Sync(scene, view_layer)
    sync.rebuild_groups()
    try:
        yield sync
    finally:
        sync.drop_scratch()
    sync.relink(scene.objects)
    sync.finish(prune)
    world_copies.follow(scene)
    remember(scene, view_layer)


def relink_scene(scene, view_layer=None, prune: bool = True) -> Sync:
    """Bring the Phong materials of *scene*'s objects up to date with its lights."""
    with session(scene, view_layer, prune) as sync:
        pass
    return sync


def remember(scene, view_layer=None) -> None:
    """Note the lights of *scene* as handled (the handler acts on the next change)."""
    key = scene.as_pointer()
    _LIGHTS[key] = lights_mod.light_objects(scene)
    _SEEN[key] = _signature(scene, view_layer, _LIGHTS[key])
    _NAMES[key] = _names(_LIGHTS[key])


def _signature(scene, view_layer, candidates):
    return lights_mod.signature(scene, view_layer, candidates)


# -- the handler -------------------------------------------------------------------------

_SEEN: dict = {}    # scene pointer -> signature of its lights when last relinked
_NAMES: dict = {}   # scene pointer -> the names of its light objects and their data then
_LIGHTS: dict = {}  # scene pointer -> its light objects (looked up again on structure changes)
_BUSY = []


def _names(lights) -> tuple:
    """The names of *lights* (light objects) and of their data, in order."""
    return tuple((obj.name, obj.data.name) for obj in lights)


def only_moved(scene, depsgraph) -> bool:
    """Whether *depsgraph*'s update cannot have changed *scene*'s lights since their last
    signature: no light data, collection or scene updated (so only objects, e.g. their
    transforms, and the World, whose drivers carry the lights' transforms: ``rig.py``), and
    the scene's light objects, their data and its World have the names they had.  A light
    drag is such an update and skips the signature (0.14 ms of a 4-5 ms update with 16
    lights at 1,000 objects on bpy 5.3.0); hiding a light (also from renders),
    retyping it, linking it, adding or deleting one updates the scene or a collection or a
    light, and a rename changes a name (measured on 5.3.0), so they still relink.  Reads no
    ``depsgraph.updates``: that walks every ID of the depsgraph (0.17 ms at 1,000 cubes)."""
    key = scene.as_pointer()
    seen, names, lights = _SEEN.get(key), _NAMES.get(key), _LIGHTS.get(key)
    if seen is None or names is None or lights is None or any(
            depsgraph.id_type_updated(kind) for kind in ("LIGHT", "COLLECTION", "SCENE")):
        return False
    world = scene.world
    try:
        return (world.name if world else None) == seen[2] and _names(lights) == names
    except ReferenceError:  # a remembered light was deleted
        return False


@contextlib.contextmanager
def paused():
    """No relink by the handler inside this block (the bake swaps lights groups for a
    render and puts them back)."""
    _BUSY.append(True)
    try:
        yield
    finally:
        _BUSY.pop()


def highlight_changed(scene, depsgraph) -> bool:
    """Whether a Phong material that *depsgraph* updated now wants a lights group of another
    highlight than its own (before 5.3, ``rig.HIGHLIGHT_VARIANTS``: its Blinn set to or away
    from exactly 0 or 1, linked, keyframed or driven).  Walks ``depsgraph.updates`` only when
    a material was updated (not when only node groups were: the lights groups' drivers); an
    edit of a material's own nodes (a driver removed) is named there as its node tree."""
    if not rig.HIGHLIGHT_VARIANTS or not depsgraph.id_type_updated("MATERIAL"):
        return False
    materials, trees = [], set()
    for update in depsgraph.updates:
        data = getattr(update.id, "original", None)
        if isinstance(data, bpy.types.Material):
            materials.append(data)
        elif isinstance(data, bpy.types.ShaderNodeTree) and data.is_embedded_data:
            trees.add(data.as_pointer())
    if trees:
        materials += [m for m in bpy.data.materials
                      if m.node_tree is not None and m.node_tree.as_pointer() in trees]
    return _other_highlight(scene, materials)


def _other_highlight(scene, materials) -> bool:
    """Whether one of *materials* (Phong materials of *scene* among them) wants a lights group
    of another highlight than the one it uses (``rig.highlight_for``)."""
    model = rig.model_of(scene)
    for material in materials:
        if not recipe.is_phong_material(material):
            continue
        node = material.node_tree.nodes.get(recipe.LIGHTS_NODE)
        tree = node.node_tree if node is not None else None
        if tree is None or rig.owner(tree) != scene:
            continue
        if rig.highlight_of(tree) != rig.highlight_for(model, recipe.blinn_constant(material)):
            return True
    return False


@persistent
def on_depsgraph_update(scene, depsgraph=None):
    """Relink *scene* when its lights changed (added, deleted, hidden, retyped, relinked),
    or a Phong material's Blinn asks for a lights group of another highlight
    (``highlight_changed``)."""
    if _BUSY or scene is None:
        return
    stale = scene.as_pointer() in engine_outputs.STALE  # a material began to blend (5.3+)
    # or a material's Blinn wants a lights group of another highlight (before 5.3)
    stale = stale or (depsgraph is not None and highlight_changed(scene, depsgraph))
    if depsgraph is not None and not stale and not any(
            depsgraph.id_type_updated(kind)
            for kind in ("OBJECT", "LIGHT", "COLLECTION", "SCENE", "WORLD")):
        return
    if depsgraph is not None and not stale and only_moved(scene, depsgraph):
        world_copies.on_drag(scene)  # copies live again after a save or a Cycles render
        return
    groups = rig.groups_of(scene)
    if not groups:
        return
    if depsgraph is not None and depsgraph.id_type_updated("SCENE"):
        world_copies.follow(scene)  # e.g. the render engine switched to or from Cycles
    # 5.3+: a Phong term pass appeared on a view layer (added by hand): the materials need
    # their AOV outputs, so the groups lose the loop part.  Not the other way round: without
    # the passes the materials still render right (Apply or Relink brings the loop back).
    passes = rig.wants_term_passes(scene) and any(
        light_loop.has_loop(t) or shadows.has_shadows(t) for t in groups)
    view_layer = depsgraph.view_layer if depsgraph is not None else None
    key = scene.as_pointer()
    structure = depsgraph is None or any(depsgraph.id_type_updated(kind)
                                         for kind in ("COLLECTION", "SCENE"))
    if structure or key not in _LIGHTS:  # objects may have come or gone: look again
        _LIGHTS[key] = lights_mod.light_objects(scene)
    try:
        signature = _signature(scene, view_layer, _LIGHTS[key])
    except ReferenceError:  # a remembered light was deleted
        _LIGHTS[key] = lights_mod.light_objects(scene)
        signature = _signature(scene, view_layer, _LIGHTS[key])
    if _SEEN.get(key) == signature and not stale and not passes:
        _NAMES[key] = _names(_LIGHTS[key])  # the light objects may have come or gone
        if depsgraph is not None and depsgraph.id_type_updated("LIGHT"):
            world_copies.on_drag(scene)  # a Power or colour dragged: park as a move does
        return
    _BUSY.append(True)
    try:
        # moving a group's users to a new group here crashes Blender (5.3.0) in such a scene
        with rig.in_place() if instances_phong(scene) else contextlib.nullcontext():
            relink_scene(scene, view_layer, prune=False)
    finally:
        _BUSY.pop()


def instances_phong(scene) -> bool:
    """Whether *scene* instances a collection (an object's Instancing ▸ Collection, at any
    depth) holding an object whose Phong material uses another scene's lights group (a
    collection of another scene's converted objects instanced here: glTF-Blender-IO's
    tests/scenes/39_parenting_full_hierarchy.blend after Apply).  A lights group of such a
    scene that moves its users to a new group (``rig.rewrite``) inside a depsgraph handler
    crashes Blender in the update that follows (bpy 5.3.0, ``deg_check_base_in_depsgraph``;
    not where the instanced materials are the scene's own), so the handler rewrites such a
    scene's groups in place."""
    here = scene.as_pointer()
    return any(recipe.lights_scene(slot.material) not in (None, here)
               for obj in lights_mod.instanced_objects(scene.objects)
               for slot in obj.material_slots)


@persistent
def forget(*_args):
    """After loading a file or an undo step the remembered fingerprints mean nothing."""
    _SEEN.clear()
    _LIGHTS.clear()
    _NAMES.clear()


@persistent
def upgrade_on_load(*_args):
    """A file of an earlier version: each scene whose lights groups are older than
    ``rig.RIG_VERSION`` is relinked, which rebuilds its groups and upgrades its Phong
    materials (``sources.upgrade``); nothing is lost.  So is a scene whose groups have the
    loop part where this Blender has no light loop (a file of 5.3 opened by 5.2: its EEVEE
    Material Outputs, of nodes 5.2 does not know, are removed) or lack it where it should
    be (a file of 5.2 opened by 5.3).  Files of version 0.1 (no lights
    groups, every light in the material) are upgraded by Relink Phong Lights.  A group with
    a variant for this release (5.3's light groups of the seeds' lights groups) is rewritten in place where the
    file has another (``loader.refresh_variants``)."""
    if _BUSY:
        return
    if compat.file_from_newer_release():
        _renew()
        return
    loader.refresh_variants()
    for scene in bpy.data.scenes:
        if scene.library is not None:
            continue
        loop = light_loop.stamp(rig.model_of(scene)) if rig.wants_loop(scene) else ""
        rays = rig.wants_shadows(scene)
        highlights = rig.highlights(rig.model_of(scene))
        if not any(int(t.get(rig.VERSION_KEY, 0)) < rig.RIG_VERSION
                   or (t.get(light_loop.LOOP_KEY) or "") != loop
                   or shadows.has_shadows(t) != rays or rig.highlight_of(t) not in highlights
                   for t in rig.groups_of(scene)):
            continue
        _BUSY.append(True)
        try:
            relink_scene(scene)
        finally:
            _BUSY.pop()


def _renew() -> None:
    """A file written by a newer Blender (5.3 read by 5.2): the lights groups' interfaces and
    the materials' group nodes evaluate wrongly here (``compat.file_from_newer_release``), so
    the groups get a new interface and are rebuilt for this release (the loop part goes where
    there is no loop), the nodes are made again, the links into them kept."""
    links = {m.as_pointer(): source_materials.group_links(m) for m in recipe.phong_materials()}
    scenes = [s for s in bpy.data.scenes if s.library is None and rig.groups_of(s)]
    for scene in scenes:
        for tree in rig.groups_of(scene):
            tree.interface.clear()
    _BUSY.append(True)
    try:
        for scene in scenes:
            relink_scene(scene)
        for material in recipe.phong_materials():
            source_materials.renew_group_node(material, links.get(material.as_pointer()))
        for scene in scenes:
            if rig.HIGHLIGHT_VARIANTS and _other_highlight(scene, recipe.phong_materials()):
                # the relink above chose by the Blinn of an unlinked input: again, as linked
                relink_scene(scene)  # (its end follows, as below)
                continue
            for follow in AFTER_FINISH:  # what reads the lights nodes' links (Per Vertex /
                # Per Face): shading.modes.refresh ran in the relink, before they were back
                follow(scene)
    finally:
        _BUSY.pop()


#: The lighting room's handlers, (event of ``bpy.app.handlers``, function) in the order they
#: run; ``addon/__init__.py`` registers every room's list, this one last.  The relink
#: handler comes after every other handler of depsgraph_update_post that reads the
#: depsgraph's updates: a relink frees and edits data blocks (groups, the World's drivers)
#: that those updates still name (Blender 4.2 crashed in follow_opacity after it); on
#: load_post the upgrade (a relink) comes last too (tests/test_register.py).
HANDLERS = (("depsgraph_update_post", opacity.follow_opacity),
            ("depsgraph_update_post", light_loop.follow_lights),
            ("depsgraph_update_post", shadows.follow_shadow_visibility),
            ("depsgraph_update_post", on_depsgraph_update), ("load_post", forget),
            ("load_post", shadows.follow_on_load), ("load_post", upgrade_on_load),
            ("undo_post", forget), ("redo_post", forget),
            *world_copies.HANDLERS)
#: The functions that relink: last of the extension's handlers on their events.
RELINKS = (on_depsgraph_update, upgrade_on_load)
