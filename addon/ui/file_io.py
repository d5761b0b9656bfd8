# SPDX-License-Identifier: GPL-3.0-or-later
"""What the File ▸ Import / Export operators of every format share (the table of formats is
``interchange/formats.py``): the run and reports of an import and an export, the check of an
export path, the lights report, the invoke of a file dropped on the 3D Viewport, its drop
handler and a format's File menu entry."""

import os

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ImportHelper

from ..interchange import formats
from ..lighting import recipe


def lights_report(op, sync) -> None:
    """Warnings every light operation gives (Apply, Relink, an import): unsupported lights,
    no light, a linking collection whose objects have no Phong material."""
    if sync.unsupported:
        names = ", ".join(f"{o.name} ({o.data.type.title()})" for o in sync.unsupported)
        op.report({"WARNING"}, f"Phong: unsupported light type ignored: {names}; only Point, "
                               "Sun, Spot and Area lights drive Phong materials")
    if not sync.lights:
        op.report({"WARNING"}, "Phong: the scene has no light that renders; the "
                               "materials show ambient and irradiant only")
    for light, rule in zip(sync.lights, sync.rules):
        if rule is None or not rule[0]:
            continue
        collection = light.light_linking.receiver_collection
        if not any(recipe.is_phong_material(slot.material) for obj in collection.all_objects
                   for slot in obj.material_slots):
            op.report({"WARNING"}, f"Phong: light {light.name!r} lights only the objects of "
                                   f"collection {collection.name!r}, and none of them has a "
                                   "Phong material")


def run_import(operator, context, key: str, **options) -> set:
    """Import *operator*'s file as the format *key* of ``formats.FORMATS`` and report as
    every import reports (its ``import_report``, "Import X3D: ..."): the file's problem
    (``formats.InterchangeError``, whose message names the file) as an error, each warning,
    the scene's lights that its Phong materials cannot use (a format without lights of its
    own, where it made objects), and what was made."""
    fmt = formats.by_key(key)
    path = bpy.path.abspath(operator.filepath)
    try:
        result = fmt.importer(context, path, **options)
    except formats.InterchangeError as error:
        operator.report({"ERROR"}, f"{fmt.import_report}: {error}")
        return {"CANCELLED"}
    for warning in result.warnings:
        operator.report({"WARNING"}, f"{fmt.import_report}: {warning}")
    if result.objects and result.sync is not None and not fmt.has_lights:
        lights_report(operator, result.sync)   # OBJ: the scene's lights light the file
    operator.report({"INFO"}, f"Imported {len(result.objects)} object(s) with "
                              f"{len(result.materials)} Phong material(s) from "
                              f"{os.path.basename(path)}")
    return {"FINISHED"}


def export_path(op, action):
    """The absolute path of *op*'s filepath, or None after an error report when it does not
    name a file in an existing folder."""
    path = bpy.path.abspath(op.filepath)
    if not path or os.path.isdir(path) or not os.path.isdir(os.path.dirname(path) or "."):
        op.report({"ERROR"}, f"{action}: {path!r} is not a file in an existing folder")
        return None
    return path


def run_export(operator, context, key: str, use_selection=False, **options) -> set:
    """Export to *operator*'s file as the format *key* when it names a file in an existing
    folder, and report as every export reports (its ``export_report``): a path or write
    error, what the scene lacks (ValueError, RuntimeError), each warning, the file written."""
    fmt = formats.by_key(key)
    label = fmt.export_report
    path = export_path(operator, label)
    if path is None:
        return {"CANCELLED"}
    try:
        warnings = fmt.exporter(context, path, use_selection, **options)
    except OSError as error:
        operator.report({"ERROR"}, f"{label}: cannot write {path}: {error.strerror or error}")
        return {"CANCELLED"}
    except (ValueError, RuntimeError) as error:
        operator.report({"ERROR"}, f"{label}: {error}")
        return {"CANCELLED"}
    for warning in warnings:
        operator.report({"WARNING"}, f"{label}: {warning}")
    operator.report({"INFO"}, f"Wrote {path}")
    return {"FINISHED"}


def glob(key: str) -> str:
    """The file browser's filter of the format *key* (``formats.Format.glob``)."""
    return formats.by_key(key).glob


class DroppableImport(ImportHelper):
    """The shared part of the import operators that take a file dropped on the 3D Viewport
    (COLLADA, X3D / VRML97, FBX): undoable, the path not remembered between runs (a path set
    before invoke is a dropped file, imported at once: :func:`invoke_import`)."""

    bl_options = {"REGISTER", "UNDO"}
    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})

    def invoke(self, context, event):
        return invoke_import(self, context, event)


def invoke_import(operator, context, event) -> set:
    """An import operator's invoke: a path set before invoke is a file dropped on the viewport
    (the drop handler), imported at once; otherwise the file browser."""
    if operator.filepath:
        return operator.execute(context)
    return ImportHelper.invoke(operator, context, event)


def drop_handler(key: str) -> list:
    """[a FileHandler class] that imports files of the format *key* dropped on the 3D
    Viewport with its import operator, or [] where the release has no
    ``bpy.types.FileHandler``."""
    if not hasattr(bpy.types, "FileHandler"):
        return []
    fmt = formats.by_key(key)

    def poll_drop(cls, context):
        return context.area is not None and context.area.type == "VIEW_3D"

    idname = f"PHONG_FH_{fmt.key}"
    return [type(idname, (bpy.types.FileHandler,), {
        "bl_idname": idname, "bl_label": fmt.drop_label,
        "bl_import_operator": fmt.import_operator,
        "bl_file_extensions": ";".join(fmt.suffixes), "poll_drop": classmethod(poll_drop)})]


def menu_entry(menu, key: str, direction: str) -> None:
    """The File ▸ Import (*direction* "import") or File ▸ Export ("export") entry of the
    format *key*: its operator and label from the table."""
    fmt = formats.by_key(key)
    if direction == "import":
        menu.layout.operator(fmt.import_operator, text=fmt.import_menu)
    else:
        menu.layout.operator(fmt.export_operator, text=fmt.export_menu)
