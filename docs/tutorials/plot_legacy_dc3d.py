"""
Reading the 1994 DC3D inputs
============================

DC3D read two files: ``dc3din``, fifteen fixed-layout records that say what to run, where the
CTH dump's cells lie, the arrival filter, the wall grids and the debris material (the report's
App. C), and ``avsout``, the CTH dump of the debris at the hand-off. impactdyn reads both
(:func:`impactdyn.io.read_dc3din`, :func:`impactdyn.io.read_avsout`) and runs the 1994 workflow
from them: ``impactdyn debris legacy dc3din avsout -o runs/legacy``. This tutorial reads the
report's ``dc3din`` (``examples/debris/legacy/dc3din``); the CTH dump it names is not shipped.
The equations DC3D solves are in :doc:`/theory/debris`.
"""

# %%
# The records, with DC3D's names and the line each came from:
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
from matplotlib.patches import Rectangle

from impactdyn import InputError
from impactdyn.io import read_dc3din

# the tutorials run from docs/tutorials
DC3DIN = Path("../../examples/debris/legacy/dc3din")
d = read_dc3din(DC3DIN)
print("run type:", d.run_type.name, f"(itype {d.itype}, jtype {d.jtype})")
for name in ("tcut", "tmin", "dencut", "mu", "lam", "rho_ref", "eta", "zeta", "eps"):
    print(f"  {name:8s} = {getattr(d, name):<10g} (line {d.lines[name]})")

# %%
# Where the CTH dump's cells lie: a block of the CTH mesh, absolute cell indices from 2
# (CTH's first real cell), with the node of cell i at xlow + (i − 2) Δx.
layout = d.avs_layout
cells = (layout.i2 - layout.i1 + 1, layout.j2 - layout.j1 + 1, layout.k2 - layout.k1 + 1)
x0 = layout.xlow + (layout.i1 - 2) * layout.dx
z0 = layout.zlow + (layout.k1 - 2) * layout.dz
print(f"dumped block: {cells[0]} x {cells[1]} x {cells[2]} cells of {layout.dx} cm")

# %%
# The wall grid the debris is deposited on, and the second grid DCPOST remaps it onto
# (records 9–12), over the wall plane y = ydmin, with the dumped block's x–z extent.
old, new = d.wall_grid, d.new_wall_grid
fig, ax = plt.subplots(figsize=(5, 6))
for grid, colour, label in ((old, "0.75", "wall grid"), (new, "tab:blue", "remap grid")):
    ax.vlines(grid.x, grid.z[0], grid.z[-1], colors=colour, linewidth=0.4)
    ax.hlines(grid.z, grid.x[0], grid.x[-1], colors=colour, linewidth=0.4, label=label)
ax.add_patch(Rectangle((x0, z0), cells[0] * layout.dx, cells[2] * layout.dz, fill=False,
                       edgecolor="tab:red", linewidth=1.5, label="CTH dump (x–z extent)"))
ax.set(xlabel="x (cm)", ylabel="z (cm)", aspect="equal",
       title=f"wall plane y = {old.y[0]} cm: {len(old.x)} x {len(old.z)} nodes")
ax.legend(loc="upper right", fontsize="small")
fig.tight_layout()

# %%
# A damaged file fails clearly, naming the file and the line: here the material record is
# cut off.
with tempfile.TemporaryDirectory() as scratch:
    truncated = Path(scratch) / "dc3din"
    truncated.write_text("".join(DC3DIN.read_text().splitlines(keepends=True)[:26]))
    try:
        read_dc3din(truncated)
    except InputError as err:
        print("InputError:", str(err).replace(scratch, "..."))
