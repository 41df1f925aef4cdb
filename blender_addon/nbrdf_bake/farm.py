"""Write Farm Plan: `nbrdf farm slurm --plan DIR -- <the bake's arguments>` for a material
whose inputs are a tile set, never submitted (docs/FARM.md, "Farm plans"): the artist's
machine needs no Slurm; the plan's submit.sh (or plan.json, for any other queue) runs on the
farm.

The farm's nodes read the maps later, from the same paths: images that exist only in
Blender (packed, generated, painted) are written into DIR/inputs/, which stays, and every
input is passed by absolute path. A file there whose bytes are unchanged is kept as it is,
so that its modification time, part of each tile's inputs fingerprint, lets a re-submitted
plan skip the tiles already baked.
"""

import filecmp
import json
import os
import shutil
import subprocess
import tempfile

import bpy

from . import inputs, preferences, tiles
from .params import PARAMS

PLAN_TIMEOUT_S = 300  # the plan reads every tile's header: seconds, not minutes


class Plan:
    def __init__(self, folder, output, tile_numbers, text):
        self.folder = folder
        self.output = output
        self.tiles = tile_numbers
        self.text = text  # nbrdf farm's own summary

    @property
    def submit(self):
        return os.path.join(self.folder, "submit.sh")

    def report(self):
        return ("farm plan of %d tile%s (%s) for %s in %s: run 'bash %s' where Slurm runs "
                "(any other queue: %s)" % (
                    len(self.tiles), "" if len(self.tiles) == 1 else "s",
                    ", ".join(str(t) for t in self.tiles), self.output, self.folder,
                    self.submit, os.path.join(self.folder, "plan.json")))


def plan_folder(settings, material_name):
    path = settings.farm_plan.replace("{material}", inputs.file_name(material_name))
    if not path.strip():
        raise inputs.SetupError("Farm Plan: choose a folder for the plan")
    if path.startswith("//") and not bpy.data.filepath:
        raise inputs.SetupError("farm plan '%s' is relative to the .blend file: save the file "
                                "first or choose an absolute folder" % settings.farm_plan)
    return os.path.normpath(bpy.path.abspath(path))


def write_plan(context, material):
    """Writes the plan; returns a Plan, or raises inputs.SetupError with the user's words."""
    exe, bundle, problem = preferences.resolve(preferences.get(context))
    if problem:
        raise inputs.SetupError(problem)
    settings = material.nbrdf_bake
    output = inputs.output_path(settings, material.name)
    folder = plan_folder(settings, material.name)
    specs, _, made = inputs.resolve_sources(context, material, settings)
    staging = tempfile.mkdtemp(prefix="nbrdf-farm-", dir=bpy.app.tempdir or None)
    try:
        if not inputs.any_tiled(specs):
            raise inputs.SetupError("material '%s': the farm plan is for a tile set, and no "
                                    "input is a tiled (UDIM) image" % material.name)
        output = inputs.set_output(output, specs)
        argv, output, _ = inputs.build_argv(exe, bundle, settings, material.name, staging,
                                            specs, output)
        os.makedirs(os.path.dirname(output), exist_ok=True)
        os.makedirs(folder, exist_ok=True)
        argv = _keep_inputs(argv, staging, os.path.join(folder, "inputs"))
    except OSError as e:
        raise inputs.SetupError("cannot prepare the farm plan: %s" % e) from e
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        for im in made:
            bpy.data.images.remove(im)
    bake_args = [a for a in argv[2:] if a != "--progress=json"]
    cmd = [exe, "farm", "slurm", "--plan", folder, "--"] + bake_args
    try:
        r = subprocess.run(cmd, cwd=os.path.dirname(output), stdin=subprocess.DEVNULL,
                           capture_output=True, text=True, errors="replace",
                           timeout=PLAN_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise inputs.SetupError("nbrdf farm slurm: %s" % e) from e
    if r.returncode != 0:
        lines = [l.strip() for l in r.stderr.splitlines() if l.strip()]
        errors = [l for l in lines if "warning:" not in l and "note:" not in l]
        raise inputs.SetupError(" ".join(errors or lines) or
                                "nbrdf farm slurm exited with status %d" % r.returncode)
    try:
        with open(os.path.join(folder, "plan.json"), encoding="utf-8") as f:
            numbers = [int(t) for t in json.load(f).get("tiles", [])]
    except (OSError, ValueError) as e:
        raise inputs.SetupError("nbrdf farm slurm wrote no readable plan.json in %s: %s"
                                % (folder, e)) from e
    return Plan(folder, output, numbers, r.stdout.strip())


def _keep_inputs(argv, staging, kept):
    """argv with each map written into `staging` moved to `kept` (unchanged files left
    alone) and every map path absolute."""
    argv = list(argv)
    for p in PARAMS:
        if p.flag not in argv:
            continue
        i = argv.index(p.flag) + 1
        name = argv[i]
        if os.path.isabs(name) or not _is_file_or_set(os.path.join(staging, name)):
            continue  # the image's own file(s), or a constant
        os.makedirs(kept, exist_ok=True)
        for f in _files_of(staging, name):
            src, dst = os.path.join(staging, f), os.path.join(kept, f)
            if not (os.path.isfile(dst) and filecmp.cmp(src, dst, shallow=False)):
                shutil.move(src, dst)
        argv[i] = os.path.join(kept, name)
    return argv


def _is_file_or_set(path):
    folder, name = os.path.split(path)
    return bool(_files_of(folder, name))


def _files_of(folder, name):
    """The files in `folder` that `name` (a file name or a tile pattern) names."""
    if not tiles.is_pattern(name):
        return [name] if os.path.isfile(os.path.join(folder, name)) else []
    match = tiles.name_regex(name)
    return sorted(e for e in os.listdir(folder) if match.match(e))
