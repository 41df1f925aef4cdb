"""Accuracy "Auto" (issue 35): the Target Error field reaches the CLI as --max-error, the bake
equals `nbrdf bake --accuracy auto` on the same constants byte for byte, and the panel's
result line says the level chosen and its held-out error (from the CLI's "done" event)."""

import filecmp
import os
import subprocess
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_testing as t  # noqa: E402

t.enable()
from nbrdf_bake import inputs  # noqa: E402
from nbrdf_bake.params import number  # noqa: E402
from nbrdf_bake.session import accuracy_summary  # noqa: E402

work = t.temp_dir()
mat = bpy.data.materials.new("AutoLacquer")
s = mat.nbrdf_bake
s.roughness = "ALPHA"
s.alpha1_value, s.eta_value, s.alpha2_value = 0.05, 1.5, 0.3
s.r0_value, s.albedo_value, s.sigma_t_value = (0.9, 0.9, 0.9), (0.5, 0.5, 0.5), 0.5
s.size_mode, s.size = "CUSTOM", (2, 2)
s.preview = False
s.output = os.path.join(work, "{material}.exr")

t.check("Target Error defaults to 5 %", abs(s.max_error - 5.0) < 1e-6)
s.accuracy, s.max_error, s.budget = "AUTO", 40.0, 2.0
argv = inputs.accuracy_argv(s)
t.check("argv %s" % argv, argv == ["--accuracy", "auto", "--max-error", "40", "--budget", "2"])
s.accuracy = "FITTED"
t.check("no --max-error for another level", "--max-error" not in inputs.accuracy_argv(s))
s.accuracy = "AUTO"

t.check("auto bake", bpy.ops.nbrdf.bake_latent(material=mat.name) == {"FINISHED"})
out = os.path.join(work, "AutoLacquer.exr")
cli = os.path.join(work, "cli.exr")
f32 = np.float32
values = {"alpha1": 0.05, "eta": 1.5, "alpha2": 0.3, "r0": 0.9, "albedo": 0.5, "sigma-t": 0.5}
params = sum((["--" + k, number(f32(v))] for k, v in values.items()), [])
run = subprocess.run([t.NBRDF, "bake", "--bundle", t.BUNDLE] + params +
                     ["--roughness", "alpha", "--size", "2x2", "--accuracy", "auto", "--max-error", "40",
                      "--budget", "2", "--progress=json", "-o", cli],
                     capture_output=True, text=True)
t.check("CLI auto bake: %s" % run.stderr, run.returncode == 0)
t.check("auto bytes equal to the CLI's", os.path.isfile(out) and filecmp.cmp(out, cli, shallow=False))
t.check("result line '%s'" % s.accuracy_result, s.accuracy_result.startswith("Auto"))
t.check("the result line names a level and a figure",
        any(w in s.accuracy_result for w in ("Fast", "Fitted", "Specialised"))
        and "%" in s.accuracy_result)

# The line for each kind of outcome.
done = {"requested": "auto", "accuracy": "specialised", "heldout_error": 0.023,
        "heldout_error_fast": 0.117, "max_error": 5, "met": True}
t.check("met", accuracy_summary(done) ==
        "Auto chose Specialised: held-out lobe error 2.3 % (target 5 %)")
done.update(met=False, accuracy="fast")
t.check("not met, fast best", accuracy_summary(done) == "Auto: no level met 5 %; Fast reached 11.7 %")
t.check("fell back", "worse than Fast" in accuracy_summary(
    {"requested": "compact", "accuracy": "fast", "fell_back": True, "heldout_error": 0.09,
     "heldout_error_fast": 0.06}))
t.check("fast: no line", accuracy_summary({"accuracy": "fast"}) == "")
t.finish("test_accuracy_auto")
