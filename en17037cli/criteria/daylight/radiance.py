"""The scene as Radiance geometry with materials, and Radiance's programs run on it.

The programs come with pyradiance's wheel (the ``daylight`` extra); this module is the only one
that starts them. The scene is written once per run in the scene's local frame (already shifted to
a local origin in float64, see :mod:`en17037cli.scene.build`), each vertex with 6 decimals [m]
(1 µm: Radiance reads decimal text into doubles). Rays go in and values come out as binary
doubles (``-fdd``), so no precision is lost there either.

Materials (visible, grey): each face takes the reflectance a layer rule gives it, else the default
of its kind (``daylight.reflectance``): interior faces by orientation (walls: steeper than 45°;
a horizontal face lying at a room's floor level over its floor is floor, at its ceiling level
ceiling, any other by the side its normal faces: up floor, down ceiling), landscape, ground.
Glazing is Radiance ``glass`` with the transmissivity :func:`glass_transmissivity` of its
normal-hemispherical transmittance; glazing given transmittance 1 is an open opening (left out).
"""
from __future__ import annotations

import io
import os
import signal
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from en17037cli.errors import InputError
from en17037cli.geometry import triangle_normals
from en17037cli.scene.model import GROUND, INTERIOR, LANDSCAPE, WINDOW, Scene

#: Radiance's luminous efficacy of its RGB radiance units [lm/W] (Radiance reference manual).
EFFICACY_LM_W = 179.0
#: Weights of R, G, B in luminance (Radiance's ``bright`` of ``rayinit.cal``).
RGB_WEIGHTS = np.array([0.265, 0.670, 0.065])
#: A face is a wall when its normal is within 45° of horizontal.
WALL_MAX_NZ = np.sqrt(0.5)
#: A horizontal face this close to a room's floor or ceiling level is that room's floor or ceiling [m].
LEVEL_TOLERANCE_M = 0.05
#: Glazing whose transmittance is at least this is an open opening: left out of the Radiance scene
#: (no glass reaches tv = 1; Radiance's glass tops out near 0.92).
OPEN_TV = 0.999
#: Decimals of the coordinates written [m]: 1 µm.
DECIMALS = 6


def glass_transmissivity(tv) -> np.ndarray:
    """Radiance ``glass`` transmissivity tn from the normal-hemispherical transmittance tv.

    Radiance's glass is a single pane with internal reflections: its transmittance at normal
    incidence is tv when tn = (sqrt(0.8402528435 + 0.0072522239 tv²) - 0.9166530661) / 0.0036261119 / tv
    (refractive index 1.52).

    Parameters
    ----------
    tv : float or array in (0, 1]

    Returns
    -------
    tn : same shape, in (0, 1]; 0 where tv is 0

    References
    ----------
    Radiance reference manual, "Glass" material (G. Ward Larson, R. Shakespeare, Rendering with
    Radiance, 1998, and ``radiance/doc/ray.html``).
    """
    tv = np.asarray(tv, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        tn = (np.sqrt(0.8402528435 + 0.0072522239 * tv**2) - 0.9166530661) / 0.0036261119 / tv
    return np.where(tv > 0, tn, 0.0)


def illuminance(rgb) -> np.ndarray:
    """Illuminance [lx] from Radiance irradiance RGB (n, 3) [W/m²]: 179 x (0.265 R + 0.670 G + 0.065 B)."""
    return EFFICACY_LM_W * (np.asarray(rgb, dtype=float).reshape(-1, 3) @ RGB_WEIGHTS)


def surface_kinds(scene: Scene) -> np.ndarray:
    """Kind of each face: 0 floor, 1 walls, 2 ceiling, 3 landscape, 4 ground, 5 glazing (see the module docstring)."""
    import shapely

    tris = scene.vertices[scene.triangles]
    normals, _ = triangle_normals(tris)
    kind = np.full(len(tris), 1, dtype=np.int8)
    interior = scene.layer == INTERIOR
    flat = interior & (np.abs(normals[:, 2]) > WALL_MAX_NZ)
    kind[flat] = np.where(normals[flat, 2] > 0, 0, 2)
    c = tris.mean(axis=1)
    for room in scene.rooms:  # a few rooms; vectorised over faces
        inside = flat & shapely.contains_xy(room.floor.buffer(1e-6), c[:, 0], c[:, 1])
        kind[inside & (np.abs(c[:, 2] - room.floor_z) < LEVEL_TOLERANCE_M)] = 0
        if np.isfinite(room.ceiling_z):
            kind[inside & (np.abs(c[:, 2] - room.ceiling_z) < LEVEL_TOLERANCE_M)] = 2
    kind[scene.layer == LANDSCAPE] = 3
    kind[scene.layer == GROUND] = 4
    kind[scene.layer == WINDOW] = 5
    return kind


KIND_NAMES = ("floor", "walls", "ceiling", "landscape", "ground")


def face_optics(scene: Scene, reflectance: dict[str, float], glazing_tv: float) -> tuple[np.ndarray, np.ndarray]:
    """Per face: its kind (:func:`surface_kinds`) and its reflectance (opaque) or transmittance tv (glazing)."""
    kind = surface_kinds(scene)
    value = np.array([reflectance[k] for k in KIND_NAMES] + [glazing_tv])[kind]
    if scene.optics is not None:
        own = np.where(kind == 5, scene.optics[:, 1], scene.optics[:, 0])
        value = np.where(np.isfinite(own), own, value)
    return kind, value


def scene_text(scene: Scene, reflectance: dict[str, float], glazing_tv: float, black: bool = False) -> str:  # pragma: no mutate block
    """The scene as Radiance primitives: one material per (kind, value) and one polygon per face.

    ``black``: every opaque face black (reflectance 0), for the direct-only daylight coefficients.
    """
    kind, value = face_optics(scene, reflectance, glazing_tv)
    if black:
        value = np.where(kind == 5, value, 0.0)
    value = np.round(value, 4)
    buf = io.StringIO()
    tris = np.round(scene.vertices[scene.triangles], DECIMALS).reshape(-1, 9)
    groups = np.unique(np.column_stack([kind, value]), axis=0)
    for k, v in groups:  # one block per material (a handful)
        if int(k) == 5 and v >= OPEN_TV:
            continue  # an open opening: no glazing at all
        name = f"{('floor', 'walls', 'ceiling', 'landscape', 'ground', 'glazing')[int(k)]}_{v:.4f}"
        if int(k) == 5:
            tn = float(glass_transmissivity(v))
            buf.write(f"void glass {name}\n0\n0\n3 {tn:.6f} {tn:.6f} {tn:.6f}\n\n")
        else:
            buf.write(f"void plastic {name}\n0\n0\n5 {v:.4f} {v:.4f} {v:.4f} 0 0\n\n")
        sel = np.flatnonzero((kind == k) & (value == v))
        rows = np.column_stack([sel, tris[sel]])
        np.savetxt(buf, rows, fmt=f"{name} polygon f%d\n0\n0\n9" + f" %.{DECIMALS}f" * 9 + "\n")
    return buf.getvalue()


#: The CIE standard overcast sky as a Radiance brightness function of the direction: L = L_z (1 + 2 Dz) / 3
#: above the horizon, the ground's constant radiance below (A1: L_z, A2: ground) [W sr⁻¹ m⁻²].
CIE_OVERCAST_CAL = "skybr = if(Dz, A1 * (1 + 2 * Dz) / 3, A2);\n"
#: File name of :data:`CIE_OVERCAST_CAL` beside an :class:`Octree`.
CIE_OVERCAST_FILE = "cieovercast.cal"


def cie_overcast_sky_text(horizontal_lx: float, ground_reflectance: float) -> str:  # pragma: no mutate block
    """The CIE standard overcast sky by its formula (CIE S 011/E:2003, sky type 16): L(γ) = L_z (1 +
    2 sin γ) / 3, with L_z = 9 E_h / (7 π) so that an unobstructed horizontal plane receives
    ``horizontal_lx``, and below the horizon the ground's radiance ρ_g E_h / π (a Lambertian ground
    of ``ground_reflectance`` under that sky). Unlike ``gensky -c`` (:func:`overcast_sky_text`), no
    blend into the ground's brightness near the horizon and no rounding of L_z to 3 digits. Needs
    :data:`CIE_OVERCAST_CAL` as :data:`CIE_OVERCAST_FILE` beside the octree
    (``Octree(..., files=sky_files())``)."""
    e = horizontal_lx / EFFICACY_LM_W  # [W/m²], Radiance's units
    lz, lg = 9.0 * e / (7.0 * np.pi), ground_reflectance * e / np.pi
    return (f"void brightfunc skyfunc\n2 skybr {CIE_OVERCAST_FILE}\n0\n2 {lz:.9g} {lg:.9g}\n\n"
            "skyfunc glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source sky\n0\n0\n4 0 0 1 180\n\n"
            "skyfunc glow groundglow\n0\n0\n4 1 1 1 0\n\ngroundglow source ground\n0\n0\n4 0 0 -1 180\n")


def sky_files() -> dict[str, str]:  # pragma: no mutate block
    """The files :func:`cie_overcast_sky_text` needs beside the octree, name -> text."""
    return {CIE_OVERCAST_FILE: CIE_OVERCAST_CAL}


def overcast_sky_text(horizontal_lx: float, ground_reflectance: float) -> str:  # pragma: no mutate block
    """The CIE standard overcast sky (``gensky -c``) giving ``horizontal_lx`` on an unobstructed
    horizontal plane, with the ground hemisphere below the horizon at ``ground_reflectance``."""
    out = run(["gensky", "-ang", "45", "0", "-c", "-B", f"{horizontal_lx / EFFICACY_LM_W:.6f}",
               "-g", f"{ground_reflectance:.4f}"]).decode()
    return out + ("\nskyfunc glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source sky\n0\n0\n4 0 0 1 180\n\n"
                  "skyfunc glow groundglow\n0\n0\n4 1 1 1 0\n\ngroundglow source ground\n0\n0\n4 0 0 -1 180\n")


def binpath() -> Path:  # pragma: no mutate block
    """Where pyradiance's Radiance programs are; an :class:`InputError` saying how to install them."""
    try:
        import pyradiance
    except ImportError:
        raise InputError("daylight: the daylight check needs Radiance through pyradiance: pip install 'en17037cli[daylight]'; "
                         "or remove the daylight section") from None
    return Path(pyradiance.BINPATH)


def run(args: list[str], stdin: bytes | None = None, cwd: Path | None = None) -> bytes:  # pragma: no mutate block
    """Run one Radiance program (from pyradiance's wheel) and return its standard output."""
    exe = binpath() / args[0]
    env = dict(os.environ)
    import pyradiance

    lib = str(Path(pyradiance.__file__).parent / "lib")
    env["RAYPATH"] = os.pathsep.join([".", lib])
    from en17037cli.scale.lifeline import program_ends_with_me

    proc = subprocess.run([str(exe), *args[1:]], input=stdin, capture_output=True, cwd=cwd, env=env, check=False,
                          preexec_fn=program_ends_with_me())  # ends with the run, even killed
    if proc.returncode == -signal.SIGINT:  # Ctrl-C reached the program too: the run is interrupted, not broken
        raise KeyboardInterrupt
    if proc.returncode != 0:
        raise RuntimeError(f"Radiance {args[0]} failed ({proc.returncode}): {proc.stderr.decode(errors='replace').strip()[:500]}")
    return proc.stdout


#: ``oconv`` options: up to 32 surfaces per octree leaf (default 6) and a resolution of 2048 (default
#: 16384). The octree only speeds up the ray intersections, which stay exact; measured on the seed
#: office (35k faces in a 240 m context): oconv 0.4 s instead of 2.9 s and a 1.5 MB octree instead
#: of 27 MB, rtrace as fast (same values to the bit).
OCONV_ARGS = ("-n", "32", "-r", "2048")


class Octree:  # pragma: no mutate block
    """The scene and a sky compiled once (``oconv``) in a temporary folder, removed by :meth:`close`.

    files : other files the scene or sky reads (a ``.cal`` of a brightness function), name -> text
    """

    def __init__(self, scene_rad: str, sky_rad: str, name: str = "scene", files: dict[str, str] | None = None):
        self._dir = tempfile.TemporaryDirectory(prefix="en17037-radiance-")
        self.dir = Path(self._dir.name)
        (self.dir / f"{name}.rad").write_text(scene_rad)
        (self.dir / "sky.rad").write_text(sky_rad)
        for fname, text in (files or {}).items():
            (self.dir / fname).write_text(text)
        self.path = self.dir / f"{name}.oct"
        self.path.write_bytes(run(["oconv", *OCONV_ARGS, "sky.rad", f"{name}.rad"], cwd=self.dir))

    def close(self) -> None:
        self._dir.cleanup()


def ambient_args(ab: int, ad: int, as_: int, lw: float) -> list[str]:  # pragma: no mutate block
    """rtrace/rcontrib ambient options: no ambient cache (``-aa 0``), so that each value is its own
    Monte Carlo estimate and replicates of a point measure its error (see
    :func:`replicate_divisions`); Radiance's default correlated sampling (``-u-``) in one process
    (``-n 1``), so that the same inputs give the same numbers (``-u+`` seeds from the clock, and
    several processes share out the rays as they come). Measured in a 6 m room at -ab 2: the mean of
    100 replicates with -u- is within 1.6 % of a -ad 16384 reference from -ad 256 on (12 % low at
    -ad 64, where -u+ is 3.5 % low): keep -ad at 256 or more."""
    return ["-n", "1", "-u-", "-ab", str(ab), "-ad", str(ad), "-as", str(as_), "-aa", "0", "-lw", f"{lw:g}"]


def rays(points: np.ndarray, direction=(0.0, 0.0, 1.0), replicates: int = 1) -> bytes:
    """Rays for ``-fd`` input: every point with ``direction``, the whole set ``replicates`` times over."""
    p = np.tile(np.asarray(points, dtype=np.float64).reshape(-1, 3), (replicates, 1))
    d = np.broadcast_to(np.asarray(direction, dtype=np.float64), p.shape)
    return np.ascontiguousarray(np.column_stack([p, d])).tobytes()


def replicate_divisions(ad: int, replicates: int) -> list[int]:
    """The ``-ad`` of each replicate, so that each lays its own stratified grid over the hemisphere:
    Radiance samples an n x n grid, n = floor(sqrt(ad w) + 0.5) (``ambcomp.c``, w the ray's weight, 1
    at a point of ``rtrace -I``), so the k-th replicate takes ad_k = (ceil(sqrt(ad)) + k)², a grid one
    division finer each time. (Until issue 36 they took ad (1 + 0.07 k), whose first two rounded to
    the same grid: 512 and 548 are both 23 x 23, and those replicates came out identical, their
    spread understating the error, down to 0.) With one grid, the replicates of Radiance's
    correlated sampling (-u-) are the same numbers."""
    n0 = int(np.ceil(np.sqrt(max(ad, 1)) - 1e-9))
    return [(n0 + k) ** 2 for k in range(replicates)]


def irradiance(octree: Octree, points: np.ndarray, ab: int, ad: int, as_: int, lw: float, replicates: int) -> np.ndarray:  # pragma: no mutate block
    """Horizontal illuminance [lx] at ``points`` (n, 3) [m, local]: one rtrace call per replicate for
    all the points (each with its own ``-ad``, :func:`replicate_divisions`).

    Returns
    -------
    (n, replicates) float [lx]: independent estimates
    """
    if not len(points):
        return np.zeros((0, replicates))
    out = []
    for k_ad in replicate_divisions(ad, replicates):  # a few calls; each vectorised over the points
        raw = run(["rtrace", "-h", "-fdd", "-I+", *ambient_args(ab, k_ad, as_, lw), octree.path.name], rays(points),
                  cwd=octree.dir)
        out.append(illuminance(np.frombuffer(raw, dtype=np.float64)))
    return np.column_stack(out)


def trace(octree: Octree, origins: np.ndarray, directions: np.ndarray, args: list[str],
          processes: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # pragma: no mutate block
    """Radiance along rays (``rtrace -ovxX``, one call for all): what each ray sees, the part of it
    that came through transmission (``x``: behind glass, or the whole value of an opaque or sky hit)
    and the distance the transmitted path travelled (``X``: at least 1e10 m, Radiance's FHUGE, when
    it ends on the sky or the ground's glow).

    Parameters
    ----------
    origins, directions : (n, 3) [m, local], unit
    args : rtrace options (:func:`ambient_args`)
    processes : rtrace programs run at once; the rays go in contiguous shares of at least
        :data:`MIN_RAYS_PER_PROCESS` (at most 8), however many run at once, so that the numbers
        (each program's own random sequence, -u-) do not depend on the machine's cores

    Returns
    -------
    value, transmitted : (n,) [cd/m²] (luminance: 179 lm/W x the RGB weights); distance : (n,) [m]
    """
    if not len(origins):
        return np.zeros(0), np.zeros(0), np.zeros(0)
    rays_in = np.ascontiguousarray(np.column_stack([origins, directions]), dtype=np.float64)
    parts = np.array_split(np.arange(len(rays_in)), max(1, min(8, len(rays_in) // MIN_RAYS_PER_PROCESS)))

    def one(idx):
        return run(["rtrace", "-h", "-fdd", "-ovxX", *args, octree.path.name], rays_in[idx].tobytes(), cwd=octree.dir)

    if len(parts) == 1 or processes <= 1:
        out = [one(idx) for idx in parts]
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(min(processes, len(parts))) as pool:  # the programs run at once; Python waits
            out = list(pool.map(one, parts))
    raw = np.frombuffer(b"".join(out), dtype=np.float64).reshape(-1, 7)
    return illuminance(raw[:, :3]), illuminance(raw[:, 3:6]), raw[:, 6]


#: Rays per share of an rtrace call (:func:`trace`; starting a program costs about as much as tracing 4096).
MIN_RAYS_PER_PROCESS = 4096
