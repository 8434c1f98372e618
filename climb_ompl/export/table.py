"""A climb's samples (:mod:`climb_ompl.export.samples`) as a CSV table or a NumPy ``.npz`` archive, written
atomically.

CSV columns: ``t`` (s since the climb began), ``step``, then for each joint ``q_<joint>``, ``v_<joint>``, ``a_<joint>``,
``tau_<joint>``, then for each limb ``f_<limb>_x``, ``_y``, ``_z`` (N, world frame).  The ``.npz`` archive holds the
same as arrays: ``t``, ``step``, ``q``, ``v``, ``a``, ``tau``, ``forces`` and the names ``joint_names``, ``limbs``.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from climb_ompl._io import atomic_write
from climb_ompl.export.samples import Samples


def csv_text(s: Samples) -> str:
    """The samples as CSV text (a header line, one row per sample, numbers to 17 significant digits)."""
    names = list(s.joint_names)
    header = ["t", "step"] + [f"{k}_{n}" for k in ("q", "v", "a", "tau") for n in names] + \
        [f"f_{lb}_{c}" for lb in s.limbs for c in "xyz"]
    body = np.column_stack([s.t, s.step, s.q, s.v, s.a, s.tau, s.forces.reshape(len(s.t), -1)])
    buf = io.StringIO()
    buf.write(",".join(header) + "\n")
    np.savetxt(buf, body, delimiter=",", fmt="%.17g")
    return buf.getvalue()


def write_csv(s: Samples, path: str | os.PathLike[str]) -> Path:
    """Write :func:`csv_text` to ``path`` atomically."""
    return atomic_write(path, csv_text(s))


def write_npz(s: Samples, path: str | os.PathLike[str]) -> Path:
    """Write the samples as a compressed ``.npz`` archive, atomically."""
    buf = io.BytesIO()
    np.savez_compressed(buf, t=s.t, step=s.step, q=s.q, v=s.v, a=s.a, tau=s.tau, forces=s.forces,
                        joint_names=np.array(s.joint_names), limbs=np.array(s.limbs), actuated=s.actuated)
    return atomic_write(path, buf.getvalue())


__all__ = ["csv_text", "write_csv", "write_npz"]
