"""Unit test of the add-on's Principled BSDF mapping table (principled.py), plain Python:
the 4.x socket names (no Blender 4 on the build machine), the 3.x ones, R0 from Base Color
and Metallic, and the rows docs/BLENDER.md prints. Run by test_principled.sh."""

import os
import sys

sys.path.insert(0, os.path.join(os.environ["NBRDF_SOURCE_DIR"], "blender_addon", "nbrdf_bake"))
import principled  # noqa: E402  (the module alone: no bpy, no package import)

failures = []


def check(what, ok):
    if not ok:
        failures.append(what)
        print("FAIL: %s" % what, file=sys.stderr)


m4 = principled.mapping((4, 2, 0))
check("4.x: coat roughness", m4["alpha1"] == ("Coat Roughness", "roughness"))
check("4.x: coat IOR", m4["eta"] == ("Coat IOR", "value"))
check("4.x: base roughness", m4["alpha2"] == ("Roughness", "roughness"))
check("4.x: base colour", m4["r0"] == ("Base Color", "base_color"))
check("4.x: coat weight", principled.COAT_WEIGHT[principled.generation((4, 0, 0))] == "Coat Weight")
m3 = principled.mapping((3, 4, 1))
check("3.x: clearcoat roughness", m3["alpha1"].socket == "Clearcoat Roughness")
check("3.x: IOR", m3["eta"].socket == "IOR")
check("3.x: clearcoat weight", principled.COAT_WEIGHT[principled.generation((3, 6, 0))] == "Clearcoat")
check("same parameters in both", set(m3) == set(m4) == set(principled.mapped_keys()))
check("albedo and sigma_t by hand", set(principled.BY_HAND) == {"albedo", "sigma_t"}
      and not set(principled.BY_HAND) & set(m4))
check("metallic 1: R0 is the colour", principled.r0_constant((0.8, 0.5, 0.3, 1.0), 1.0) == [0.8, 0.5, 0.3])
check("metallic 0: R0 is 0.04", principled.r0_constant((0.8, 0.5, 0.3), 0.0) == [0.04] * 3)
r = principled.r0_constant((1.0, 0.0, 0.5), 0.5)
check("metallic 0.5: the mix %s" % r, all(abs(a - b) < 1e-12 for a, b in zip(r, [0.52, 0.02, 0.27])))
check("metallic clamped", principled.r0_constant((1, 1, 1), 2.0) == [1.0, 1.0, 1.0])
rows = principled.table_rows((4, 1, 0))
check("rows name every 4.x socket", {s for _, s, _ in rows} >= {"Coat Roughness", "Coat IOR",
                                                                "Roughness", "Base Color", "Coat Weight"})
# docs/BLENDER.md prints the table: every socket of both generations appears there.
doc = open(os.path.join(os.environ["NBRDF_SOURCE_DIR"], "docs", "BLENDER.md")).read()
for gen in (3, 4):
    for key, src in principled.MAPPING[gen].items():
        check("docs/BLENDER.md names '%s' (%d.x)" % (src.socket, gen), src.socket in doc)
print("unit_principled: %d failed" % len(failures))
sys.exit(1 if failures else 0)
