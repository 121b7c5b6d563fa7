"""A checkpoint written in parts under MPI (`[parallel] checkpoint_per_rank`,
issue 31 item 5) continued from Python: `Scene.from_checkpoint` and
`Scene.restore` read the index and merge the parts, as the CLI does without
mpirun. Needs Open MPI's `mpirun` and a `dembound` built with MPI."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

import dembound
from conftest import REPO, binary

LATTICE = REPO / "examples" / "scenes" / "lattice_drop.toml"
# The lattice drop cut to 8 x 8 x 10 spheres in a 10.2 mm box, Walton-Braun
# (every contact's largest overlap is state): contacts from about step 1,600.
SMALL = [
    "particles.0.lattice.counts=[8,8,10]",
    "domain.upper=[0.0102,0.0102,0.03]",
    "wall.1.plane.point=[0.0102,0.0,0.0]",
    "wall.3.plane.point=[0.0,0.0102,0.0]",
    "contact.law=walton-braun",
    "contact.restitution=0.5",
]


def mpirun(ranks: int, sets: list[str], out) -> None:
    args = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)]
    args += [str(binary()), "scene", str(LATTICE), "--quiet", "--out", str(out)]
    for s in SMALL + sets:
        args += ["--set", s]
    done = subprocess.run(args, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="needs Open MPI's mpirun")
def test_restart_from_parts_is_the_gathered_checkpoints_restart(tmp_path):
    # The same 2-rank run checkpointed at step 2000 in parts and gathered
    # (the merged parts are the gathered checkpoint, every field: the
    # crate's decomposition_checkpoint_parts tests). The reference: Python
    # continuing the gathered checkpoint, 1000 steps.
    steps = ["integration.steps=2000"]
    mpirun(2, steps + ["parallel.checkpoint_per_rank=true"], tmp_path / "parts")
    mpirun(2, steps, tmp_path / "gathered")
    index = tmp_path / "parts" / "checkpoint.cbor"
    for r in range(2):
        assert (tmp_path / "parts" / f"checkpoint_rank_{r}.cbor").exists()
    sets = SMALL + ["integration.steps=3000"]
    gathered = dembound.Scene.from_checkpoint(tmp_path / "gathered" / "checkpoint.cbor")
    gathered.step(1000)
    loaded = dembound.Scene.from_checkpoint(index)
    assert loaded.steps_done == 2000
    loaded.step(1000)
    assert np.array_equal(loaded.positions, gathered.positions)
    assert np.array_equal(loaded.velocities, gathered.velocities)
    again = dembound.Scene.from_toml(LATTICE, sets=sets)
    again.restore(index)
    assert again.steps_done == 2000
    again.step(1000)
    assert np.array_equal(again.positions, gathered.positions)
    # The contacts are in play: the state is not the free fall's.
    assert again.observe()["particle_contacts"] > 0
    # A part damaged (one byte changed): refused, named.
    part = tmp_path / "parts" / "checkpoint_rank_1.cbor"
    data = bytearray(part.read_bytes())
    data[len(data) // 2] ^= 1
    part.write_bytes(bytes(data))
    with pytest.raises(ValueError, match="checkpoint_rank_1.cbor"):
        dembound.Scene.from_checkpoint(index)
