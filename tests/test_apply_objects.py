# SPDX-License-Identifier: GPL-3.0-or-later
"""Apply Phong Material converts every object that renders with materials, as an artist's
file holds them: text, curves, meta balls, the objects of an instanced collection, an object
whose mesh is linked from a library (its slots take the Phong material on the object; the
library file is never written); a library's collection that an Empty instances and a library's
object linked into the scene (through library overrides made here: the library file is never
written); Restore gives back exactly what was there."""

from __future__ import annotations

import os

import numpy as np
import pytest

import blender_env as be


def _principled(bpy, name, color):
    """A Principled material of base colour *color* and Specular IOR Level 0: no specular
    layer, so under the ambient light alone its Phong version shows the base colour itself
    (Ka = Kd), which the picture is searched for."""
    material = bpy.data.materials.new(name)
    be.compat().new_material_tree(material)
    node = material.node_tree.nodes["Principled BSDF"]
    node.inputs["Base Color"].default_value = (*color, 1)
    node.inputs["Specular IOR Level"].default_value = 0.0
    return material


def _library(bpy, path):
    """A library file: collection "Props" holding mesh "Crate" (material "Wood") and the
    mesh data "Slab" (material "Stone")."""
    be.reset_empty_file()
    collection = bpy.data.collections.new("Props")
    bpy.context.scene.collection.children.link(collection)
    crate = be.add_quad(bpy.context.scene, "Crate", -0.5, -0.5, 0.5, 0.5, 0.1)
    bpy.context.scene.collection.objects.unlink(crate)
    collection.objects.link(crate)
    crate.data.materials.append(_principled(bpy, "Wood", (0.5, 0.3, 0.1)))
    slab = bpy.data.meshes.new("Slab")
    slab.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    slab.materials.append(_principled(bpy, "Stone", (0.35, 0.4, 0.45)))
    slab.use_fake_user = True
    bpy.data.libraries.write(path, {collection, slab}, fake_user=True)
    be.reset_empty_file()


def test_apply_converts_every_object_that_renders(bpy_clean, tmp_path):
    bpy = bpy_clean
    library = str(tmp_path / "library.blend")
    _library(bpy, library)
    before_library = os.path.getmtime(library), os.path.getsize(library)
    scene = be.new_scene("Objects", 48, 16)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 1.0  # no light: Phong Color = Object Color
    scene.world.phong.ambient_color = (1.0, 1.0, 1.0)
    be.add_ortho_camera(scene, (0.0, 0.0), 12.0, 4.0)

    text = bpy.data.curves.new("Title", "FONT")
    text.body = "W"
    text.size = 3.0
    text.materials.append(_principled(bpy, "Ink", (0.8, 0.1, 0.1)))
    title = bpy.data.objects.new("Title", text)
    title.location = (-5.5, -1.0, 0.0)
    scene.collection.objects.link(title)

    curve = bpy.data.curves.new("Rail", "CURVE")
    curve.dimensions = "3D"
    curve.bevel_depth = 0.5
    spline = curve.splines.new("POLY")
    spline.points.add(1)
    spline.points[0].co, spline.points[1].co = (-1.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 1.0)
    curve.materials.append(_principled(bpy, "Brass", (0.7, 0.6, 0.2)))
    rail = bpy.data.objects.new("Rail", curve)
    rail.location = (-0.5, 0.0, 0.0)
    scene.collection.objects.link(rail)

    ball = bpy.data.metaballs.new("Blob")
    ball.elements.new().radius = 1.0
    ball.materials.append(_principled(bpy, "Gel", (0.1, 0.7, 0.3)))
    blob = bpy.data.objects.new("Blob", ball)
    blob.location = (2.5, 0.0, 0.0)
    scene.collection.objects.link(blob)

    props = bpy.data.collections.new("Local props")  # not in the scene: instanced only
    box = be.add_quad(scene, "Box", -0.5, -0.5, 0.5, 0.5)
    scene.collection.objects.unlink(box)
    props.objects.link(box)
    box.data.materials.append(_principled(bpy, "Card", (0.2, 0.2, 0.9)))
    instance = bpy.data.objects.new("Props here", None)
    instance.instance_type, instance.instance_collection = "COLLECTION", props
    instance.location = (5.0, 0.0, 0.0)
    scene.collection.objects.link(instance)

    with bpy.data.libraries.load(library, link=True) as (data_from, data_to):
        data_to.collections = ["Props"]
        data_to.meshes = ["Slab"]
    linked = bpy.data.objects.new("Linked props", None)
    linked.instance_type, linked.instance_collection = "COLLECTION", data_to.collections[0]
    linked.location = (-1.5, 1.4, 0.0)
    scene.collection.objects.link(linked)
    floor = bpy.data.objects.new("Floor", data_to.meshes[0])  # local object, linked mesh
    floor.location = (0.0, 0.0, -3.0)
    scene.collection.objects.link(floor)

    selected = [title, rail, blob, instance, linked, floor]
    be.apply_phong(scene, selected)
    for obj in (title, rail, blob, box, floor):
        names = [slot.material.name for slot in obj.material_slots]
        assert all(name.startswith("Phong ") for name in names), f"{obj.name}: {names}"
    assert floor.material_slots[0].link == "OBJECT", "the library's mesh is left as it is"
    assert data_to.meshes[0].materials[0].name == "Stone"
    library_crate = next(o for o in bpy.data.objects if o.name == "Crate" and o.library)
    assert library_crate.material_slots[0].material.name == "Wood", "the library's is kept"
    override = linked.instance_collection
    assert override.library is None and override.override_library is not None, \
        "the Empty instances a library override of the library's collection"
    assert override.override_library.reference == data_to.collections[0]
    assert override.name not in scene.collection.children, "the Empty alone shows it"
    crate = override.objects[0]
    assert crate.material_slots[0].material.name.startswith("Phong "), crate.name

    from phong_nodes.addon.lighting import convert  # noqa: PLC0415  (needs bpy)

    scene.collection.objects.link(library_crate)  # a library's object linked in directly
    report = convert.apply(scene, [library_crate])
    assert report.skipped == [] and len(report.converted) == 1, report.text()
    direct = next(o for o in scene.collection.objects if o.name.startswith("Crate"))
    assert direct.override_library is not None and direct.library is None
    assert direct.override_library.reference == library_crate
    assert library_crate.name not in [o.name for o in scene.collection.objects
                                      if o.library is not None], "the override took its place"
    assert direct.material_slots[0].material.name.startswith("Phong ")

    path = str(tmp_path / "objects.exr")
    be.render_exr(scene, path)
    combined = be.read_multilayer_exr(path)["Combined"][..., :3]
    for name, colour in (("Title", (0.8, 0.1, 0.1)), ("Rail", (0.7, 0.6, 0.2)),
                         ("Blob", (0.1, 0.7, 0.3)), ("Card", (0.2, 0.2, 0.9)),
                         ("Wood", (0.5, 0.3, 0.1))):
        found = np.abs(combined - np.array(colour)).max(axis=2) <= 1e-5
        assert found.sum() >= 3, f"{name}: its base colour is in the Phong picture"

    be.apply_phong(scene, selected)  # again: nothing new
    assert linked.instance_collection == override, "one override, made once"
    for obj in scene.objects:
        obj.select_set(obj in selected or obj == direct)
    assert bpy.ops.phong.restore_materials() == {"FINISHED"}
    assert linked.instance_collection == data_to.collections[0], "the library's again"
    assert "phong_instance_override" not in linked.keys()
    assert [c.name for c in bpy.data.collections if c.override_library] == [], "dropped"
    assert [o.name for o in bpy.data.objects if o.override_library] == [], "dropped"
    assert library_crate.name in scene.collection.objects and \
        scene.collection.objects[library_crate.name] == library_crate
    assert [s.material.name for s in title.material_slots] == ["Ink"]
    assert [s.material.name for s in box.material_slots] == ["Card"]
    assert floor.material_slots[0].link == "DATA" and floor.material_slots[0].material.name == \
        "Stone"
    assert "phong_object_slots" not in floor.keys()
    assert (os.path.getmtime(library), os.path.getsize(library)) == before_library


def test_restore_after_a_reload_gives_a_users_override_its_library_slots_back(bpy_clean,
                                                                             tmp_path):
    """An override the user made of a library's collection keeps its mesh linked: Apply puts
    the Phong material in the object's slot (linked to the object) and notes it; a reload
    drops that note (an override keeps no custom property its library's object lacks), yet
    Restore after the reload links the slot to the library's mesh again, as it was."""
    bpy = bpy_clean
    library = str(tmp_path / "library.blend")
    _library(bpy, library)
    scene = be.new_scene("Override", 16, 16)
    bpy.context.window.scene = scene
    with bpy.data.libraries.load(library, link=True) as (_, data_to):
        data_to.collections = ["Props"]
    scene.collection.children.link(data_to.collections[0])
    layer = scene.view_layers[0]
    data_to.collections[0].override_hierarchy_create(scene, layer)
    crate = next(o for o in bpy.data.objects if o.override_library is not None)
    assert crate.data.library is not None, "the user's override keeps the library's mesh"
    be.apply_phong(scene, [crate])
    slot = crate.material_slots[0]
    assert slot.link == "OBJECT" and slot.material.name.startswith("Phong "), slot.material
    path = str(tmp_path / "override.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    crate = next(o for o in bpy.data.objects if o.override_library is not None)
    assert crate.material_slots[0].material.name.startswith("Phong "), "kept by the override"
    assert "phong_object_slots" not in crate.keys(), "Blender drops the note (else: no test)"

    from phong_nodes.addon.lighting import convert  # noqa: PLC0415  (needs bpy)

    assert convert.restore(crate) == 1
    slot = crate.material_slots[0]
    assert slot.link == "DATA" and slot.material.name == "Wood" and \
        slot.material.library is not None, (slot.link, slot.material)


def test_a_scene_instancing_another_scenes_phong_objects_follows_its_lights(bpy_clean,
                                                                             tmp_path):
    """Scene "B" holds a collection of converted objects (their Phong materials use B's lights
    group) that scene "A" instances, beside A's own converted objects.  After a reload A's
    lights change (an object moved, then a light added): the handler relinks A, which must
    neither crash Blender (moving a lights group's users to a new group inside the handler
    did, bpy 5.3.0: glTF-Blender-IO's 39_parenting_full_hierarchy.blend after Apply) nor
    miss the new light."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import rig, sync

    be.reset_empty_file()
    scene_a = be.new_scene("A", 8, 8)
    scene_b = be.new_scene("B", 8, 8)
    props = bpy.data.collections.new("Props")
    scene_b.collection.children.link(props)
    for index in range(2):
        card = be.add_quad(scene_b, f"Card {index}", 0.0, 0.0, 1.0, 1.0, 0.0)
        scene_b.collection.objects.unlink(card)
        props.objects.link(card)
        card.location.x = 2.0 * index
        card.data.materials.append(_principled(bpy, f"Card {index}", (0.2, 0.5, 0.8)))
    own = []
    for index in range(2):  # two materials: A's lights group has two users
        tile = be.add_quad(scene_a, f"Tile {index}", 0.0, 0.0, 1.0, 1.0, 0.0)
        tile.location.y = 3.0 + index
        tile.data.materials.append(_principled(bpy, f"Tile {index}", (0.8, 0.5, 0.2)))
        own.append(tile)
    instancer = bpy.data.objects.new("Props here", None)
    instancer.instance_type, instancer.instance_collection = "COLLECTION", props
    scene_a.collection.objects.link(instancer)
    light = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    light.location = (0.0, 0.0, 3.0)
    scene_a.collection.objects.link(light)
    for scene, objects in ((scene_b, list(props.objects)), (scene_a, own)):
        bpy.context.window.scene = scene
        bpy.context.view_layer.update()
        be.apply_phong(scene, objects)
    assert sync.instances_phong(scene_a) and not sync.instances_phong(scene_b)
    path = str(tmp_path / "instancing.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    scene_a = bpy.data.scenes["A"]
    bpy.context.window.scene = scene_a
    scene_a.objects["Tile 0"].location.x += 1.0
    bpy.context.view_layer.update()  # the handler's first relink after the load: no crash
    lamp = bpy.data.objects.new("Second lamp", bpy.data.lights.new("Second lamp", "SPOT"))
    lamp.location = (1.0, 1.0, 3.0)
    scene_a.collection.objects.link(lamp)
    bpy.context.view_layer.update()
    for name in ("Tile 0", "Tile 1"):
        material = scene_a.objects[name].active_material
        group = material.node_tree.nodes["phong_lights"].node_tree
        assert rig.owner(group) == scene_a
        assert sorted(str(n) for n in group.get("phong_lights", ())) == [
            "Lamp", "Second lamp"], f"{name}: A's lights group follows its lights"
    card = bpy.data.objects["Card 0"].active_material.node_tree.nodes["phong_lights"]
    assert rig.owner(card.node_tree) == bpy.data.scenes["B"], "B's objects keep B's group"


def test_compare_sees_the_objects_of_an_instanced_collection(bpy_clean, tmp_path):
    """A collection that only an Empty instances (no object of it in the view layer), its
    objects converted by Apply: the comparison finds them (it said "no object with a Phong
    material … Apply Phong Material first" after Apply itself had converted them), and
    Cycles matches the reference on their instances' pixels."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.scene import describe

    be.reset_empty_file()
    scene = be.new_scene("Instances", 32, 32)
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (0.0, 0.0), 4.0, 4.0)
    props = bpy.data.collections.new("Props")  # not linked to the scene: instanced only
    card = be.add_quad(scene, "Card", -0.8, -0.8, 0.8, 0.8, 0.0)
    scene.collection.objects.unlink(card)
    props.objects.link(card)
    card.data.materials.append(_principled(bpy, "Card", (0.2, 0.5, 0.8)))
    instancers = []
    for index, x in enumerate((-1.0, 1.0)):
        instancer = bpy.data.objects.new(f"Props {index}", None)
        instancer.instance_type, instancer.instance_collection = "COLLECTION", props
        instancer.location = (x, 0.0, 0.0)
        scene.collection.objects.link(instancer)
        instancers.append(instancer)
    light = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    light.location = (0.3, 0.2, 2.0)
    scene.collection.objects.link(light)
    bpy.context.view_layer.update()
    be.apply_phong(scene, instancers)
    layer = describe.view_layer_of(scene)
    assert describe.phong_objects(scene, layer) == [], "nothing of it in the view layer"
    assert describe.instanced_phong_objects(scene, layer) == [card]
    metrics = engine.run(scene, str(tmp_path / "out"), engines=("cycles",))
    assert metrics["ok"], metrics.get("verdict")
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    assert metrics["pixels"]["compared"] > 200, "both instances' pixels are compared"


def _points_modifier(bpy, obj, material=None):
    """A Geometry Nodes modifier on *obj* that turns its mesh into points (Mesh to Points,
    which drops the mesh's materials), given *material* by a Set Material node if any."""
    tree = bpy.data.node_groups.new(f"{obj.name} points", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    group_in = tree.nodes.new("NodeGroupInput")
    group_out = tree.nodes.new("NodeGroupOutput")
    points = tree.nodes.new("GeometryNodeMeshToPoints")
    tree.links.new(group_in.outputs[0], points.inputs["Mesh"])
    out = points.outputs["Points"]
    if material is not None:
        setter = tree.nodes.new("GeometryNodeSetMaterial")
        setter.inputs["Material"].default_value = material
        tree.links.new(out, setter.inputs["Geometry"])
        out = setter.outputs["Geometry"]
    tree.links.new(out, group_out.inputs[0])
    modifier = obj.modifiers.new("Points", "NODES")
    modifier.node_group = tree
    return modifier


def test_compare_says_when_geometry_nodes_drop_the_phong_materials(bpy_clean):
    """An object whose Geometry Nodes turn its mesh into points without its material renders
    no Phong surface after Apply: Apply's report and the comparison say so (it failed with "the camera sees 0
    pixels … frame the scene", from a camera it had framed itself); with a Set Material of
    the object's Phong material on the points it has something to compare again."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.lighting import convert

    be.reset_empty_file()
    scene = be.new_scene("Points", 16, 16)
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (0.0, 0.0), 2.0, 2.0)
    card = be.add_quad(scene, "Card", -0.8, -0.8, 0.8, 0.8, 0.0)
    card.data.materials.append(_principled(bpy, "Card", (0.2, 0.5, 0.8)))
    modifier = _points_modifier(bpy, card)
    light = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    light.location = (0.3, 0.2, 2.0)
    scene.collection.objects.link(light)
    bpy.context.view_layer.update()
    report = convert.apply(scene, [card])  # what Object ▸ Apply Phong Material runs
    assert report.converted == ["Card"]
    assert any(note.startswith("'Card': renders no Phong surface") for note in report.notes), \
        report.notes
    with pytest.raises(engine.ComparisonError, match=r"'Card'\) render no Phong surface"):
        engine.check(scene)
    modifier.show_viewport = False  # hidden in the viewport: the render's geometry counts
    with pytest.raises(engine.ComparisonError, match="render no Phong surface"):
        engine.check(scene)
    card.modifiers.remove(modifier)
    _points_modifier(bpy, card, card.active_material)
    assert engine.check(scene)[1] == [card]
    assert not [n for n in convert.apply(scene, [card]).notes if "no Phong surface" in n]


def test_the_walk_of_collection_instances_takes_each_object_once_and_can_keep_to_the_render(
        bpy_clean):
    """``lights.instanced_objects``, the one walk of Apply, the relink handler and the
    comparison: an Empty instancing collection "Set" (objects a, then b instancing "Inner";
    a child collection "Off", disabled in renders, holding c) brings a, b, what b instances
    (e) and then c, depth first; a second Empty of "Set" brings nothing again; keeping to the
    render leaves "Off" out, and an object disabled in renders with what it instances."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import lights  # noqa: PLC0415  (needs bpy)

    scene = bpy.context.scene

    def collection(name, *objects, parent=None):
        made = bpy.data.collections.new(name)
        (parent.children if parent is not None else scene.collection.children).link(made)
        for obj in objects:
            made.objects.link(obj)
        return made

    def empty(name, instances=None):
        obj = bpy.data.objects.new(name, None)
        if instances is not None:
            obj.instance_type, obj.instance_collection = "COLLECTION", instances
        return obj

    e = be.add_quad(scene, "e", 0, 0, 1, 1, 0)
    scene.collection.objects.unlink(e)
    inner = collection("Inner", e)
    a, b = be.add_quad(scene, "a", 0, 0, 1, 1, 0), empty("b", inner)
    scene.collection.objects.unlink(a)
    c = be.add_quad(scene, "c", 0, 0, 1, 1, 0)
    scene.collection.objects.unlink(c)
    setting = collection("Set", a, b)
    collection("Off", c, parent=setting).hide_render = True
    for made in (setting, inner):
        scene.collection.children.unlink(made)
    first, second = empty("First", setting), empty("Second", setting)
    for obj in (first, second):
        scene.collection.objects.link(obj)

    def names(objects, **kw):
        return [obj.name for obj in lights.instanced_objects(objects, **kw)]

    assert names([first, second]) == ["a", "b", "e", "c"]
    assert names([first, second], with_objects=True) == ["First", "a", "b", "e", "c", "Second"]
    assert names([first, second], rendering=True) == ["a", "b", "e"]
    b.hide_render = True
    assert names([first], rendering=True) == ["a"]
    assert names([first]) == ["a", "b", "e", "c"]
    assert names([a]) == []  # a plain object instances nothing


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_apply_and_compare_name_what_the_engines_read_differently(bpy_clean, tmp_path):
    """A source whose Base Color is an image whose file is gone, one whose Image Texture
    node holds no image, one whose Attribute node has no name: Apply's report names them
    (Cycles shows a missing image magenta and Eevee black; Cycles reads 0 for the unnamed
    attribute and Eevee the active colour attribute), and so does the comparison with Eevee,
    whose picture then misses the reference; once the file is there, the node has its image
    and the attribute its name, neither says anything."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.lighting import convert  # noqa: PLC0415  (needs bpy)

    scene = be.new_scene("Missing", 24, 16)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 1.0
    be.add_ortho_camera(scene, (0.0, 0.0), 6.0, 4.0)
    texture_path = tmp_path / "wood.png"
    maker = bpy.data.images.new("maker", 4, 4)
    maker.filepath_raw, maker.file_format = str(texture_path), "PNG"
    maker.save()
    bpy.data.images.remove(maker)
    content = texture_path.read_bytes()
    image = bpy.data.images.load(str(texture_path))
    image.name = "Wood"
    os.remove(texture_path)
    nodes = []
    for index, (name, picture) in enumerate((("Wood", image), ("Blank", None), ("Paint", None))):
        material = _principled(bpy, name, (0.5, 0.5, 0.5))
        if name == "Paint":  # an Attribute node of no name: Cycles 0, Eevee the active colour
            node = material.node_tree.nodes.new("ShaderNodeAttribute")
        else:
            node = material.node_tree.nodes.new("ShaderNodeTexImage")
            node.image = picture
        material.node_tree.links.new(node.outputs["Color"],
                                     material.node_tree.nodes["Principled BSDF"]
                                     .inputs["Base Color"])
        quad = be.add_quad(scene, f"Card {index}", -2.9 + 2.0 * index, -1.0, -1.1 + 2.0 * index,
                           1.0, 0.0)
        quad.data.materials.append(material)
        nodes.append(node)
    report = convert.apply(scene)
    missing = [n for n in report.notes if n.startswith("missing image(s)")]
    assert len(missing) == 1, report.notes
    assert f"'Wood' ({texture_path})" in missing[0]
    assert "no image in 'Image Texture' of 'Phong Blank'" in missing[0]
    assert "Attribute node(s) without a name: 'Attribute' of 'Phong Paint': Cycles reads 0 " \
        "there, Eevee the active colour attribute; give each the attribute's name" in report.notes
    metrics = engine.run(scene, str(tmp_path / "compare"), engines=("cycles", "eevee"))
    said = [n for n in metrics.get("notes", []) if n.startswith(("missing image(s)",
                                                                "Attribute node(s)"))]
    assert len(said) == 2 and all(n.endswith("so Eevee's picture differs there")
                                  for n in said), metrics

    texture_path.write_bytes(content)  # the file is back
    phong_blank = bpy.data.materials["Phong Blank"]
    for node in phong_blank.node_tree.nodes:
        if node.bl_idname == "ShaderNodeTexImage":
            node.image = image
    for node in bpy.data.materials["Phong Paint"].node_tree.nodes:
        if node.bl_idname == "ShaderNodeAttribute":
            node.attribute_name = "Col"
    assert not convert.engine_notes([bpy.data.materials["Phong Wood"], phong_blank,
                                     bpy.data.materials["Phong Paint"]])
    metrics = engine.run(scene, str(tmp_path / "again"), engines=("cycles", "eevee"))
    assert not [n for n in metrics.get("notes", []) if "missing image" in n
                or "without a name" in n], metrics["notes"]


def test_an_object_saved_in_edit_mode_renders_its_faces_for_the_comparison(bpy_clean):
    """An object in Edit Mode (glTF-Blender-IO's 11_loose_geometry.blend is saved so) has an
    evaluated mesh that lists no faces to Python, yet renders them: the comparison's check
    of what renders counts it (it refused the file: "render no Phong surface") and the note
    of warped polygons sees its faces."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.scene import describe  # noqa: PLC0415

    scene = be.new_scene("Editing", 24, 16)
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (0.0, 0.0), 6.0, 4.0)
    mesh = bpy.data.meshes.new("Bent")
    mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0.4), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    mesh.materials.append(_principled(bpy, "Clay", (0.5, 0.4, 0.3)))
    card = bpy.data.objects.new("Bent card", mesh)
    scene.collection.objects.link(card)
    be.apply_phong(scene, [card])
    layer = scene.view_layers[0]
    bpy.context.view_layer.objects.active = card
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        evaluated = card.evaluated_get(describe.evaluated(scene, layer)).data
        assert card.mode == "EDIT" and not len(evaluated.polygons), "the wrapper lists faces now"
        assert describe.rendering_phong(scene, layer, [card]) == [card]
        engine.check(scene)  # no "render no Phong surface"
        notes = describe.warped_notes(scene, layer, [card])
        assert len(notes) == 1 and notes[0].startswith("'Bent card': 1 flat polygon(s)"), notes
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
