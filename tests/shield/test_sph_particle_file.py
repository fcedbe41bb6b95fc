"""The SPH particle file round-trips every array and refuses what it did not write (issue 4)."""

import h5py
import numpy as np
import pytest

from impactdyn import InputError
from impactdyn.shield import History, fragments_of, read_fragments, sphere_on_plate, write_fragments
from impactdyn.shield._io import read_particles, write_particles


def test_particles_and_history_round_trip(tmp_path):
    p = sphere_on_plate("al6061-t6", "al2024-t4", 0.4, 7.0, 25.0, 0.127, 0.1).particles
    h = History(time=np.array([0.0, 0.1]), mass=np.ones(2), momentum=np.ones((2, 3)), kinetic=np.ones(2),
                internal=np.zeros(2))
    write_particles(tmp_path / "p.h5", p, h)
    q, g = read_particles(tmp_path / "p.h5")
    assert q.materials == p.materials == ("al6061-t6", "al2024-t4") and q.time == p.time
    for name in ("position", "velocity", "mass", "density", "deviatoric_stress", "failed", "material"):
        np.testing.assert_array_equal(getattr(q, name), getattr(p, name))
    np.testing.assert_array_equal(g.momentum, h.momentum)
    write_particles(tmp_path / "p2.h5", p)
    assert read_particles(tmp_path / "p2.h5")[1] is None


def test_foreign_files_are_refused(tmp_path):
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = [1.0]
    with pytest.raises(InputError, match="not an impactdyn SPH particle file"):
        read_particles(tmp_path / "other.h5")
    (tmp_path / "text.h5").write_text("hello")
    with pytest.raises(InputError, match="not an HDF5 file"):
        read_particles(tmp_path / "text.h5")
    with pytest.raises(InputError, match="no such file"):
        read_particles(tmp_path / "missing.h5")


def test_fragments_round_trip_exactly_and_foreign_files_are_refused(tmp_path):
    p = sphere_on_plate("al6061-t6", "al6061-t6", 0.4, 2.0, 0.0, 0.127, 0.05).particles
    fragments = fragments_of(p, link_length_cm=0.075)
    assert len(fragments) > 0
    write_fragments(tmp_path / "f.h5", fragments)
    back = read_fragments(tmp_path / "f.h5")
    for name in ("mass", "position", "velocity", "spin", "diameter_cm", "axes_cm", "count", "ptr", "members",
                 "from_failed"):
        np.testing.assert_array_equal(getattr(back, name), getattr(fragments, name))
        assert getattr(back, name).dtype == getattr(fragments, name).dtype
    write_particles(tmp_path / "p.h5", p)
    with pytest.raises(InputError, match="not an impactdyn fragments file"):
        read_fragments(tmp_path / "p.h5")
