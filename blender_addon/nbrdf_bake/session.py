"""One bake of one material: inputs written, CLI running, result loaded, temp files gone;
then, when asked for and available, a preview render of the texture.

The operator is a thin shell over this: execute() calls start() then wait(); the modal
invoke() calls start() and then poll() on a timer. Tests drive it the same way.
"""

import os
import re
import shutil
import subprocess
import tempfile
import time

import bpy

from . import inputs, material_inputs, preferences, tiled_images, tiles
from .params import PARAMS, range_lines
from .process import BakeProcess


NODE_NAME = "nbrdf latent texture"
VERIFY_TEXELS = 16
VERIFY_SPP = 16  # walks per lobe image and run: ~0.5 CPU-s per distinct texel, a rough figure



def accuracy_summary(done):
    """The panel's line for the CLI's "done" event: the level the texture is at and its
    held-out lobe error; auto's choice and target; a fallback to fast. Empty for fast."""
    if not done or "requested" not in done:
        return ""
    level = done.get("accuracy", "fast").capitalize()
    err = 100.0 * float(done.get("heldout_error", 0.0))
    fast = 100.0 * float(done.get("heldout_error_fast", 0.0))
    if done["requested"] == "auto":
        if level == "Fast":
            err = fast
        if done.get("met"):
            return "Auto chose %s: held-out lobe error %.1f %% (target %g %%)" % (
                level, err, done.get("max_error", 0.0))
        return "Auto: no level met %g %%; %s reached %.1f %%" % (
            done.get("max_error", 0.0), level, err)
    if done.get("fell_back"):
        return "%s was worse than Fast (%.1f %% against %.1f %%): baked Fast" % (
            done["requested"].capitalize(), err, fast)
    return "%s: held-out lobe error %.1f %% (Fast %.1f %%)" % (level, err, fast)

class Session:
    def __init__(self, material_name, bake, workdir, verify_argv, preview_argv, notes, made):
        self.material_name = material_name
        self.bake = bake
        self.verify = None
        self.preview = None
        self.process = bake  # the one running now
        self.workdir = workdir
        self.verify_argv = verify_argv
        self.preview_argv = preview_argv
        self.notes = notes  # from reading the material
        self.made = made  # images of the UV bake, removed at the end
        self.image = None
        self.preview_image = None
        self.node = None
        self.relative = False  # the output was asked for relative to the .blend (//)
        self.files = {}  # temporary input file -> what the user knows it as
        self.flags = {}  # a tiled input's option (--alpha2) -> what the user knows it as
        self.cwd = workdir  # where the CLI runs: the output's folder when inputs are relative
        self._stopped = False

    @classmethod
    def start(cls, context, material, obj=None, template=None, uv_map=None, extras=True):
        """Starts a bake; raises inputs.SetupError with a message the user can act on.

        The queue passes `obj` (whose UV map `uv_map` a procedural input is baked over),
        `template` (its output path, with {object} and {material}) and extras=False (no
        verify, no preview)."""
        exe, bundle, problem = preferences.resolve(preferences.get(context))
        if problem:
            raise inputs.SetupError(problem)
        settings = material.nbrdf_bake
        output = inputs.output_path(settings, material.name, template,
                                    obj.name if obj is not None else None)
        specs, notes, made = inputs.resolve_sources(context, material, settings, obj, uv_map)
        output = inputs.set_output(output, specs)
        workdir = tempfile.mkdtemp(prefix="nbrdf-bake-", dir=bpy.app.tempdir or None)
        try:
            argv, output, params = inputs.build_argv(exe, bundle, settings, material.name,
                                                     workdir, specs, output)
            os.makedirs(os.path.dirname(output), exist_ok=True)
            cwd = workdir
            relative = _relative_inputs(argv, params, output, specs)
            if relative is not None:
                argv, params = relative
                cwd = os.path.dirname(output)
        except (inputs.SetupError, OSError) as e:
            shutil.rmtree(workdir, ignore_errors=True)
            _remove_images(made)
            if isinstance(e, OSError):
                raise inputs.SetupError("cannot prepare the bake: %s" % e) from e
            raise
        verify_argv = None
        if settings.verify and extras:
            verify_argv = [exe, "verify", output] + params + [
                "--bundle", bundle, "--texels", str(VERIFY_TEXELS), "--spp", str(VERIFY_SPP),
                "--json", os.path.join(workdir, "verify.json"), "--progress=json"]
        preview_argv = None
        if settings.preview and extras and tiles.is_pattern(output):
            notes = notes + ["no preview of a tile set (nbrdf render takes one tile's texture)"]
        elif settings.preview and extras and has_render(exe):
            size = str(settings.preview_size)
            preview_argv = [exe, "render", output, "-o", preview_path(output), "--bundle", bundle,
                            "--width", size, "--height", size, "--spp",
                            str(settings.preview_spp), "--progress=json"]
        bake = BakeProcess(argv, output, cwd=cwd)
        session = cls(material.name, bake, workdir, verify_argv, preview_argv, notes, made)
        session.relative = (template or settings.output).startswith("//")
        session.cwd = cwd
        words = _input_words(material, specs, made)
        session.files = _file_words(argv, specs, words) if cwd == workdir else {}
        session.flags = {p.flag: words[p.key] for p in PARAMS if specs[p.key][0] == "image"
                         and tiled_images.is_tiled(specs[p.key][1])}
        if not bake.start():
            session._cleanup()
            raise inputs.SetupError(bake.message)
        return session

    @property
    def stage(self):
        if self.process is self.preview:
            return "preview"
        return "verify" if self.process is self.verify else "bake"

    @property
    def ranges(self):
        """The bake's range report in the panel's words (params.range_lines)."""
        return range_lines(self.bake.ranges)

    @property
    def progress(self):
        return self.process.progress

    @property
    def step_name(self):
        """The CLI's own stage within this one (a fitted bake: ground truth, fit, bake)."""
        return self.process.step_name

    @property
    def cancelling(self):
        return self.process.cancelling

    @property
    def tile_text(self):
        """"tile 1002 (2/3): 40 %" while a tile set's tile is in progress, else ""."""
        p = self.process
        if not getattr(p, "tiles", 0) or not p.tile:
            return ""
        return "tile %d (%d/%d): %.0f %%" % (p.tile, p.tile_index, p.tiles,
                                            100.0 * p.tile_progress)

    def poll(self):
        """True while running; at the end the inputs are removed and the results loaded."""
        if self.process.poll():
            return True
        material = bpy.data.materials.get(self.material_name)
        if self.process is self.bake:
            if material is not None:
                material.nbrdf_bake.range_report = "\n".join(self.ranges)
            if self.bake.state != "done":
                self._cleanup()
                return False
            if self.bake.tiled:
                self.image = tiled_images.load_result(self.bake.output, self.relative)
            else:
                self.image = load_result(self.bake.output, self.relative)
            if material is not None:
                material.nbrdf_bake.result = self.image
                material.nbrdf_bake.accuracy_result = accuracy_summary(self.bake.result)
                self.node = add_image_node(material, self.image)
                material.nbrdf_bake.verify_texels = 0
            if self.verify_argv and not self._stopped:
                self.verify = BakeProcess(self.verify_argv, self.verify_argv[-2],
                                          cwd=self.cwd)
                self.process = self.verify
                if self.verify.start():
                    return True
        elif self.process is self.verify and self.verify.state == "done" and material:
            r = self.verify.result
            s = material.nbrdf_bake
            s.verify_median = float(r.get("median_pct", -1.0))
            s.verify_worst = float(r.get("worst_pct", -1.0))
            s.verify_texels = int(r.get("texels", 0))
        if self.process is not self.preview:
            self._cleanup()
            if self.preview_argv and not self._stopped:
                self.preview = BakeProcess(self.preview_argv, preview_path(self.bake.output))
                self.process = self.preview
                return self.preview.start()
            return False
        if self.preview.state == "done":
            self.preview_image = load_result(self.preview.output, self.relative)
            if material is not None:
                material.nbrdf_bake.preview_image = self.preview_image
        return False

    def wait(self, interval=0.05):
        while self.poll():
            time.sleep(interval)
        return self.bake.state

    def cancel(self):
        self._stopped = True
        self.process.cancel()

    def report(self):
        """(level, text) for Blender's report area once the session has ended."""
        b = self.bake
        if b.state == "cancelled":
            return "WARNING", "nbrdf: bake " + b.message
        if b.state != "done":
            return "ERROR", "; ".join(["nbrdf bake failed: " + self.explain(b.message)]
                                      + self.ranges)
        r = b.result
        notes = list(self.notes) + self.ranges + list(b.warnings)
        v = self.verify
        if v is not None and v.state == "done" and v.result:
            info = "verify: median lobe error %.1f %%, worst %.1f %% (%d texels)" % (
                v.result.get("median_pct", -1), v.result.get("worst_pct", -1),
                v.result.get("texels", 0))
        elif v is not None:
            info = None
            notes.append("verify cancelled" if v.state == "cancelled"
                         else "verify failed: " + (v.message or v.state))
        else:
            info = None
        if self.preview is not None and self.preview.state != "done":
            notes.append("preview not rendered: " + self.preview.message)
        if b.tiled:
            text = "nbrdf: baked %s (%s tiles: %s baked, %s skipped as up to date)" % (
                b.output, r.get("tiles"), r.get("baked"), r.get("skipped"))
        else:
            text = "nbrdf: baked %s (%s x %s, %s)" % (
                b.output, r.get("width"), r.get("height"),
                "rgb" if r.get("channels") == 3 else "mono")
        return ("WARNING" if notes else "INFO"), "; ".join([text] + ([info] if info else [])
                                                           + notes)

    def explain(self, message):
        """The CLI's message with each temporary input file named as the user knows it
        (the UV bake of a node, a generated image): the user never saw those files. A tiled
        input the message names by its option (tiles that disagree) is named as the user
        knows it too: its image and the Image Texture node it comes from."""
        for name in sorted(self.files, key=len, reverse=True):
            message = message.replace(name, self.files[name])
        cited = [f for f in sorted(self.flags) if re.search(re.escape(f) + r"(?![-\w])",
                                                             message)]
        if cited:
            message += " (%s)" % "; ".join("%s: %s" % (f, self.flags[f]) for f in cited)
        return message

    def _cleanup(self):
        shutil.rmtree(self.workdir, ignore_errors=True)
        _remove_images(self.made)
        self.made = []


def _remove_images(images):
    for im in images:
        try:
            bpy.data.images.remove(im)
        except (ReferenceError, RuntimeError):
            pass


def _relative_inputs(argv, params, output, specs):
    """(argv, params) with each image file named relative to the output's folder, for the
    CLI to run there, so that the texture's nbrdf:parameterSources names the maps as they lie
    beside it (`r0=../textures/rust.png`); None when an input is one of the add-on's temporary
    files (named by their own file names, relative to the temporary folder) or no image is
    given. A file whose only common folder with the output is the root keeps its absolute
    path."""
    outdir = os.path.dirname(output)
    images = [p for p in PARAMS if specs[p.key][0] == "image" and p.flag in argv]
    if not images:
        return None
    paths = [argv[argv.index(p.flag) + 1] for p in images]
    if not all(os.path.isabs(x) for x in paths):
        return None

    def rel(path):
        try:
            common = os.path.commonpath([path, outdir])
            if os.path.dirname(common) == common:  # only the root (or another drive)
                return path
            return os.path.relpath(path, outdir)
        except ValueError:
            return path

    out = []
    for lst in (argv, params):
        lst = list(lst)
        for p in images:
            if p.flag in lst:
                i = lst.index(p.flag) + 1
                lst[i] = rel(lst[i])
        out.append(lst)
    return out[0], out[1]


def _input_words(material, specs, made):
    """{parameter key: the user's words for its image}: the UV bake of a node, an image of
    an Image Texture node of the material, or an image chosen in the panel."""
    try:
        reading = material_inputs.read(material)[0]
    except material_inputs.MaterialError:
        reading = {}
    out = {}
    for p in PARAMS:
        kind, value = specs[p.key]
        if kind != "image":
            continue
        from_material = getattr(material.nbrdf_bake, p.key + "_source") == "MATERIAL"
        r = reading.get(p.key) if from_material else None
        if value in made and r is not None and r.kind == "procedural":
            out[p.key] = "the UV bake of material '%s', input '%s' from %s" % (
                material.name, r.socket, inputs.node_words(r.value))
        elif r is not None and r.kind == "image" and r.value == value and r.node:
            out[p.key] = "image '%s' of node '%s' (material '%s', input '%s')" % (
                value.name, r.node, material.name, r.socket)
        else:
            out[p.key] = "image '%s'" % value.name
    return out


def _file_words(argv, specs, words):
    """{file the CLI is given in the temporary folder: the user's words for it}; a tile
    pattern's tiles too ("image 'rough' tile 1002")."""
    out = {}
    for p in PARAMS:
        kind, value = specs[p.key]
        if kind != "image" or p.flag not in argv:
            continue
        path = argv[argv.index(p.flag) + 1]
        if os.path.isabs(path):
            continue  # the image's own file: the user knows it
        out[path] = words[p.key]
        if tiled_images.is_tiled(value):
            for n in tiled_images.numbers(value):
                out[tiles.tile_path(path, n)] = "%s tile %d" % (words[p.key], n)
    return out


def add_image_node(material, image):
    """An Image Texture node showing the latent texture, labelled and not connected, so the
    texture travels with the .blend; reused on the next bake."""
    if not material.use_nodes or material.node_tree is None:
        return None
    nodes = material.node_tree.nodes
    node = nodes.get(NODE_NAME)
    if node is None or node.type != "TEX_IMAGE":
        node = nodes.new("ShaderNodeTexImage")
        node.name = NODE_NAME
        xs = [n.location.x for n in nodes if n is not node] or [0.0]
        ys = [n.location.y for n in nodes if n is not node] or [0.0]
        node.location = (min(xs) - 320.0, max(ys) + 60.0)
    node.label = NODE_NAME
    node.image = image
    return node


def preview_path(output):
    return os.path.splitext(output)[0] + ".preview.exr"


# (path, mtime) -> whether that executable has `render`; asked once, not on every bake.
_render_support = {}


def has_render(exe):
    """Whether this nbrdf has the render subcommand (older builds answer 'unknown')."""
    try:
        key = (exe, os.stat(exe).st_mtime_ns)
    except OSError:
        return False
    if key not in _render_support:
        try:
            _render_support[key] = subprocess.run(
                [exe, "render", "--help"], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL, timeout=30).returncode == 0
        except (OSError, subprocess.TimeoutExpired):
            return False
    return _render_support[key]


def load_result(path, relative=False):
    """An EXR as an image datablock, reloaded when one already shows that file. The latent
    texture becomes MULTILAYER (layers latent and proxy) once Blender reads its header.
    `relative`: its path stored relative to the .blend (//...), as the output was asked."""
    image = None
    for im in bpy.data.images:
        if im.filepath and os.path.normpath(bpy.path.abspath(im.filepath)) == path:
            image = im
            break
    if image is None:
        image = bpy.data.images.load(path)
    else:
        image.reload()
    # Reading the size makes Blender open the file and see its layers now. (Setting a colour
    # space here would turn it back into a plain IMAGE: float EXR data is never converted.)
    image.size[0]
    if relative and bpy.data.filepath:
        try:
            image.filepath = bpy.path.relpath(path)
        except ValueError:  # another drive: stays absolute
            pass
    return image
