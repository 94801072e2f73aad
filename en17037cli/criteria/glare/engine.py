"""Radiance runs of the glare check: the scene compiled once, its skies, the rays from the eyes, the
daylight coefficients of the eye's vertical illuminance, the sky matrices of the usage hours and the
reference fisheyes with evalglare.

The scene is the daylight criterion's Radiance writer (:func:`~en17037cli.criteria.daylight.
radiance.scene_text`, materials by kind, ``glass`` glazing) without the faces a layer rule says do
not block the sun (``obstructs_sun: false``, bare trees): they block neither the sun nor the sky
here, as in clause 5.3. It is compiled once (``oconv``, about 3 s for the seed office's 35,000
faces); each sky is added to that octree (``oconv -i``, 0.5 s). The programs run through
:func:`~en17037cli.criteria.daylight.radiance.run` (pyradiance's binaries).
"""
from __future__ import annotations

import dataclasses
import shutil
import tempfile
from pathlib import Path

import numpy as np

from en17037cli.criteria.daylight import radiance
from en17037cli.criteria.glare.dgp import reinhart_bins
from en17037cli.scene.model import WINDOW, Scene

#: Sky and ground hemispheres of unit radiance for the coefficients: ``skyglow`` (binned into
#: Reinhart patches by rcontrib) and ``groundglow`` (one bin, gendaymtx's row 0).
PATCH_SKY = ("void glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source skydome\n0\n0\n4 0 0 1 180\n\n"
             "void glow groundglow\n0\n0\n4 1 1 1 0\n\ngroundglow source grounddome\n0\n0\n4 0 0 -1 180\n")
#: What turns gensky's and gendaylit's sky function into the sky and ground hemispheres.
SKY_GLOWS = ("\nskyfunc glow skyglow\n0\n0\n4 1 1 1 0\n\nskyglow source sky\n0\n0\n4 0 0 1 180\n\n"
             "skyfunc glow groundglow\n0\n0\n4 1 1 1 0\n\ngroundglow source ground\n0\n0\n4 0 0 -1 180\n")


def glare_scene(scene: Scene) -> Scene:
    """The scene without the opaque faces that do not block the sun (see the module docstring)."""
    keep = (scene.layer == WINDOW) | scene.obstructs_sun
    if keep.all():
        return scene
    return dataclasses.replace(scene, triangles=scene.triangles[keep], layer=scene.layer[keep],
                               obstructs_sun=scene.obstructs_sun[keep], part=scene.part[keep],
                               optics=None if scene.optics is None else scene.optics[keep])


class Octrees:
    """The glare scene compiled once in a temporary folder, and octrees of it with each sky."""

    def __init__(self, scene_rad: str):
        self._dir = tempfile.TemporaryDirectory(prefix="en17037-glare-")
        self.dir = Path(self._dir.name)
        (self.dir / "scene.rad").write_text(scene_rad)
        (self.dir / "scene.oct").write_bytes(radiance.run(["oconv", "scene.rad"], cwd=self.dir))
        self._n = 0

    def with_sky(self, sky_rad: str, name: str | None = None) -> str:
        """An octree of the scene with ``sky_rad`` added; its file name in :attr:`dir`."""
        self._n += 1
        name = name or f"sky{self._n}"
        (self.dir / f"{name}.rad").write_text(sky_rad)
        (self.dir / f"{name}.oct").write_bytes(radiance.run(["oconv", "-i", "scene.oct", f"{name}.rad"], cwd=self.dir))
        return f"{name}.oct"

    def drop(self, octree: str) -> None:
        """Remove an octree no longer needed (each is as large as the scene)."""
        (self.dir / octree).unlink(missing_ok=True)

    def close(self) -> None:
        self._dir.cleanup()


def rays(origins, directions) -> bytes:
    """Rays for ``-fd`` input: origin and direction per row."""
    o = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    d = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    o = np.broadcast_to(o, d.shape) if len(o) == 1 else o
    return np.ascontiguousarray(np.column_stack([o, d])).tobytes()


def view_transmission(octrees: Octrees, octree: str, eye, directions) -> tuple[np.ndarray, np.ndarray]:
    """How much of the sky and of the ground hemisphere each direction from the eye sees, through
    every pane on its way: rcontrib -ab 0 with the unit-radiance ``skyglow`` and ``groundglow`` of
    :data:`PATCH_SKY` (a direction that meets an opaque face sees neither).

    Returns
    -------
    sky, ground : (n,) float in [0, 1]
    """
    args = ["rcontrib", "-h", "-fdd", "-n", "1", "-ab", "0", "-lw", "1e-6", "-m", "skyglow", "-m", "groundglow", octree]
    raw = np.frombuffer(radiance.run(args, rays(eye, directions), cwd=octrees.dir), dtype=np.float64)
    v = raw.reshape(-1, 2, 3) @ radiance.RGB_WEIGHTS
    return v[:, 0], v[:, 1]


def eye_coefficients(octrees: Octrees, octree: str, eyes, view_dirs, mf: int, ab: int, ad: int, lw: float,
                     replicates: int) -> np.ndarray:
    """Daylight coefficients of the vertical illuminance at each eye, facing its view direction:
    rcontrib -I with the Reinhart sky MF and the ground, one call per replicate (each its own -ad,
    :func:`~en17037cli.criteria.daylight.radiance.replicate_divisions`).

    Returns
    -------
    (replicates, n, bins) float [lx per unit radiance, W sr⁻¹ m⁻²], bins in gendaymtx's order
    """
    n = len(view_dirs)
    bins = reinhart_bins(mf)
    out = np.zeros((replicates, n, bins))
    if not n:
        return out
    for k, k_ad in enumerate(radiance.replicate_divisions(ad, replicates)):  # a few calls, each for every eye
        args = ["rcontrib", "-h", "-fdd", "-I+", *radiance.ambient_args(ab, k_ad, 0, lw), "-f", "reinhartb.cal", "-e",
                f"MF:{mf}", "-b", "rbin", "-bn", "Nrbins", "-m", "skyglow", "-b", "0", "-bn", "1", "-m", "groundglow", octree]
        raw = np.frombuffer(radiance.run(args, rays(eyes, view_dirs), cwd=octrees.dir), dtype=np.float64)
        c = radiance.illuminance(raw.reshape(-1, 3)).reshape(n, bins)
        out[k] = np.column_stack([c[:, bins - 1:], c[:, :bins - 1]])  # ground first, as gendaymtx's rows
    return out


def sky_matrix(wea: str, mf: int, north_deg: float, ground_reflectance: float, part: str) -> np.ndarray:
    """gendaymtx of a .wea text: (bins, rows) radiance per patch [W sr⁻¹ m⁻², visible] of the sky
    alone (``part="sky"``, -s) or the sun alone (``"sun"``, -d, spread into its patches), the sky
    turned so that its north lies ``north_deg`` clockwise from the model's +y."""
    with tempfile.TemporaryDirectory(prefix="en17037-wea-") as d:
        (Path(d) / "site.wea").write_text(wea)
        g = f"{ground_reflectance:.4f}"
        raw = radiance.run(["gendaymtx", "-h", "-od", "-m", str(mf), "-r", f"{-north_deg:.6f}", "-g", g, g, g,
                            "-s" if part == "sky" else "-d", "site.wea"], cwd=Path(d))
    m = np.frombuffer(raw, dtype=np.float64).reshape(reinhart_bins(mf), -1, 3)
    return m @ radiance.RGB_WEIGHTS


def reinhart_solid_angles(mf: int) -> np.ndarray:
    """Solid angle of each bin of the Reinhart sky MF [sr] (bin 0, the ground: 2 π): rows of equal
    altitude steps 90 / (7 MF + 0.5) deg, the zenith cap above the last (reinhart.cal; Jones's
    ``cmglare.c``)."""
    rings = np.repeat(np.array([30, 30, 24, 24, 18, 12, 6]) * mf, mf)
    alpha = np.radians(90.0 / (7 * mf + 0.5))
    edges = np.sin(np.arange(len(rings) + 1) * alpha)
    band = 2.0 * np.pi * np.diff(edges) / rings
    return np.concatenate([[2.0 * np.pi], np.repeat(band, rings), [2.0 * np.pi * (1.0 - edges[-1])]])


def sky_text(program: str, month: int, day: int, hour: float, lat: float, lon: float, meridian_deg: float,
             north_deg: float, ground_reflectance: float, dni: float = 0.0, dhi: float = 0.0) -> str:
    """A sky for one moment, turned to the model's north: ``gensky +s`` (the CIE clear sky with sun)
    or ``gendaylit -W`` (the Perez all-weather sky of a direct normal and diffuse horizontal
    irradiance [W/m²]); Radiance's longitudes and meridians are west-positive."""
    site = ["-a", f"{lat:.4f}", "-o", f"{-lon:.4f}", "-m", f"{-meridian_deg:.1f}"]
    when = [str(month), str(day), f"{hour:.4f}"]
    if program == "gensky":
        args = ["gensky", *when, "+s", *site, "-g", f"{ground_reflectance:.4f}"]
    else:
        args = ["gendaylit", *when, *site, "-g", f"{ground_reflectance:.4f}", "-W", f"{max(dni, 0.0):.1f}", f"{max(dhi, 0.0):.1f}"]
    text = radiance.run(args).decode()
    with tempfile.TemporaryDirectory(prefix="en17037-sky-") as d:
        (Path(d) / "sky.rad").write_text(text)
        turned = radiance.run(["xform", "-rz", f"{-north_deg:.6f}", "sky.rad"], cwd=Path(d)).decode()
    return turned + SKY_GLOWS


def view_args(eye, view_dir) -> list[str]:
    """Radiance's view options of a 180 deg angular fisheye from ``eye`` along ``view_dir``, z up."""
    e, v = np.asarray(eye, float), np.asarray(view_dir, float)
    return ["-vta", "-vv", "180", "-vh", "180", "-vp", *(f"{x:.6f}" for x in e), "-vd", *(f"{x:.6f}" for x in v), "-vu", "0", "0", "1"]


def fisheye(octrees: Octrees, octree: str, eye, view_dir, resolution: int, ab: int, ad: int, aa: float, ar: int,
            name: str) -> Path:
    """A 180 deg angular fisheye (``rpict -vta``) from ``eye`` along ``view_dir`` (z up), written to
    ``name`` in the octrees' folder: the picture evalglare reads."""
    view = view_args(eye, view_dir)
    args = ["rpict", *view, "-x", str(resolution), "-y", str(resolution), "-ps", "1", "-pj", "0", "-ab", str(ab), "-ad", str(ad),
            "-as", "0", "-aa", f"{aa:g}", "-ar", str(ar), "-lw", "1e-3", "-u-", octree]
    path = octrees.dir / name
    path.write_bytes(radiance.run(args, cwd=octrees.dir))
    return path


def evalglare(picture: Path) -> tuple[float, float]:
    """(DGP, vertical illuminance [lx]) of a fisheye picture by evalglare at its defaults (read by
    name from the detailed output's last line, ``dgp,av_lum,E_v,...: values``)."""
    out = radiance.run(["evalglare", "-d", picture.name], cwd=picture.parent).decode().strip().splitlines()[-1]
    names, values = out.split(":", 1)
    got = dict(zip(names.split(","), (float(x) for x in values.split())))
    return got["dgp"], got["E_v"]


#: A pixel brighter than this is the sun's disc seen directly [cd/m²]: the disc of a sun of 14 lx direct normal
#: illuminance through glass; the brightest sky, by the sun, is below 1e5 (Perez).
SUN_PIXEL_CD_M2 = 2e5


def angular_pixel_solid_angles(n: int) -> np.ndarray:
    """(n, n) solid angle of each pixel of an ``n`` x ``n`` 180 deg angular fisheye (-vta) [sr]:
    (π / n)² sin θ / θ, θ the pixel centre's angle from the view; 0 outside the circle."""
    y, x = np.mgrid[0:n, 0:n]
    r = np.hypot((x + 0.5) / n * 2 - 1, (y + 0.5) / n * 2 - 1)
    th = r * np.pi / 2
    om = (np.pi / n) ** 2 * np.where(th > 0, np.sin(th) / np.where(th > 0, th, 1.0), 1.0)
    return np.where(r <= 1, om, 0.0)


def write_picture(path: Path, lum: np.ndarray, view: str) -> None:
    """A grey Radiance picture (uncompressed RGBE) of luminance ``lum`` (rows, cols) [cd/m²], top row
    first, with the view line ``view`` (``-vta -vp ...``)."""
    v = np.asarray(lum, float) / radiance.EFFICACY_LM_W
    m, e = np.frexp(v)
    px = np.zeros(v.shape + (4,), np.uint8)
    px[..., :3] = np.where(v > 1e-30, np.floor(m * 256.0), 0).astype(np.uint8)[..., None]
    px[..., 3] = np.where(v > 1e-30, e + 128, 0)
    head = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nVIEW= {view}\n\n-Y {v.shape[0]} +X {v.shape[1]}\n".encode()
    path.write_bytes(head + px.tobytes())


def sun_corrected(picture: Path, view: str) -> tuple[Path, float]:
    """The fisheye with the sun's disc drawn on as many pixels as its solid angle covers, carrying its
    whole energy. rpict samples each pixel at its centre (-ps 1 -pj 0), so the disc (0.533 deg,
    6.8e-5 sr) covers as many pixels as have their centre on it, and evalglare, which merges them into
    one source of their mean luminance and summed solid angle, weighs E² / ω_pixels instead of
    E² / ω_sun (E = L ω_sun, L the disc's luminance through the glazing as Radiance rendered it, the
    brightest pixel above :data:`SUN_PIXEL_CD_M2`): anything from nothing (no centre on it) to several
    times too little. The k = round(ω_sun / ω_pixel) pixels nearest the disc's centre (at least one:
    one at 400 px, four at 800) get E / Σ ω; its other pixels the median of the sky around them.
    Returns the picture (``picture`` itself without the sun in it) and E over the energy the disc's
    pixels had (1 where there is no sun)."""
    from en17037cli.criteria.glare.dgp import SUN_SOLID_ANGLE_SR

    lum = luminance_picture(picture)
    top = float(lum.max()) if lum.size else 0.0
    if top < SUN_PIXEL_CD_M2 or lum.shape[0] != lum.shape[1]:
        return picture, 1.0
    om = angular_pixel_solid_angles(lum.shape[0])
    sun = lum > 0.5 * top
    rows, cols = np.nonzero(sun)
    w = om[sun]
    cy, cx = float((rows * w).sum() / w.sum()), float((cols * w).sum() / w.sum())
    k = max(1, int(round(SUN_SOLID_ANGLE_SR / float(om[int(round(cy)), int(round(cx))] or w.mean()))))
    pad = int(np.ceil(np.sqrt(k))) + 2
    r0, c0 = max(rows.min() - pad, 0), max(cols.min() - pad, 0)
    box_r, box_c = np.mgrid[r0:rows.max() + pad + 1, c0:cols.max() + pad + 1]
    box_r, box_c = np.minimum(box_r, lum.shape[0] - 1), np.minimum(box_c, lum.shape[1] - 1)
    near = np.argsort(np.hypot(box_r - cy, box_c - cx), axis=None, kind="stable")[:k]
    kr, kc = box_r.ravel()[near], box_c.ravel()[near]
    around = lum[box_r, box_c][~sun[box_r, box_c] & (om[box_r, box_c] > 0)]
    energy = top * SUN_SOLID_ANGLE_SR
    factor = energy / float((lum[sun] * w).sum())
    lum = np.where(sun, float(np.median(around)) if around.size else 0.0, lum)
    lum[kr, kc] = energy / float(om[kr, kc].sum())
    out = picture.with_name(picture.stem + "-sun.hdr")
    write_picture(out, lum, view)
    return out, factor


def luminance_picture(picture: Path) -> np.ndarray:
    """The luminance of a Radiance picture [cd/m²], (rows, columns) top row first (``pvalue``)."""
    head = radiance.run(["getinfo", "-d", picture.name], cwd=picture.parent).decode().split()
    ny, nx = int(head[-3]), int(head[-1])
    raw = radiance.run(["pvalue", "-h", "-H", "-b", "-df", picture.name], cwd=picture.parent)
    return radiance.EFFICACY_LM_W * np.frombuffer(raw, dtype=np.float32).astype(float).reshape(ny, nx)


def keep_picture(picture: Path, to: Path) -> None:
    """Copy a rendered picture out of the temporary folder."""
    shutil.copyfile(picture, to)
