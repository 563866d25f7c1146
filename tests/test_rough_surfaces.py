"""Rough surfaces: self-affine synthesis against its spectrum, statistics, the reader."""
import numpy as np
import pytest

from brakewear.errors import InputError, RoughnessError
from brakewear.rough import (
    Topography,
    hurst_fit,
    radial_psd,
    read_topography,
    rms_height,
    rms_slope,
    self_affine,
    self_affine_psd,
)

L = 1e-3


@pytest.mark.parametrize("hurst", [0.3, 0.8])
def test_random_phase_surface_has_the_asked_statistics_exactly(hurst):
    t = self_affine(128, L, hurst, rms_height=2e-6, rolloff=L / 4, cutoff=L / 32, seed=3)
    assert t.periodic and t.shape == (128, 128) and t.pixel == (L / 128, L / 128)
    assert abs(t.heights.mean()) < 1e-12 * 2e-6
    assert rms_height(t) == pytest.approx(2e-6, rel=1e-12)
    s = self_affine(128, L, hurst, rms_slope=0.1, rolloff=L / 4, cutoff=L / 32, seed=3)
    assert rms_slope(s) == pytest.approx(0.1, rel=1e-12)
    # a band-limited surface four pixels per shortest wavelength: central differences
    # see most of the slope, never more
    fd = rms_slope(s, "difference")
    assert 0.8 * 0.1 < fd < 0.1, fd


@pytest.mark.parametrize("hurst", [0.3, 0.5, 0.8])
def test_psd_slope_gives_back_the_hurst_exponent(hurst):
    """Between roll-off and cut-off C(q) ~ q^(-2(1+H)); the fit of the ring averages
    returns H within 0.03 (random phases: the spectrum is exact, the rings' binning is not)."""
    n = 256
    t = self_affine(n, L, hurst, rms_height=1e-6, rolloff=L / 4, cutoff=L / 64, seed=1)
    q_r, q_s = 2 * np.pi / (L / 4), 2 * np.pi / (L / 64)
    H = hurst_fit(t, 1.5 * q_r, 0.9 * q_s)
    assert H == pytest.approx(hurst, abs=0.03), H
    q, C = radial_psd(t)
    # the ring averages integrate back to the variance
    assert C[q > 0].sum() > 0
    plateau = C[(q < 0.9 * q_r) & (C > 0)]
    assert np.ptp(np.log(plateau)) < 0.2, "flat below the roll-off"
    assert np.all(C[q > 1.1 * q_s] < 1e-20 * C.max()), "nothing above the cut-off"


def test_gaussian_amplitudes_scatter_around_the_asked_statistics():
    """Gaussian Fourier coefficients: the rms height scatters from seed to seed around the
    asked one; over 16 seeds the mean is within 5 % and the Hurst fit within 0.06."""
    hs, Hs = [], []
    for seed in range(16):
        t = self_affine(128, L, 0.7, rms_height=1e-6, rolloff=L / 4, cutoff=L / 32, seed=seed,
                        amplitudes="gaussian")
        hs.append(rms_height(t))
        Hs.append(hurst_fit(t, 1.5 * 2 * np.pi / (L / 4), 0.9 * 2 * np.pi / (L / 32)))
    hs = np.array(hs)
    assert np.std(hs) > 0.01 * 1e-6, "Gaussian amplitudes scatter"
    assert np.mean(hs) == pytest.approx(1e-6, rel=0.05), np.mean(hs)
    assert np.mean(Hs) == pytest.approx(0.7, abs=0.06), np.mean(Hs)


def test_one_seed_is_one_surface_on_every_grid():
    """The modes are drawn per wavevector: 128 pixels sample the 64-pixel surface finer."""
    kw = dict(rms_height=1e-6, rolloff=L / 4, cutoff=L / 16, seed=11)
    c, f = self_affine(64, L, 0.8, **kw), self_affine(128, L, 0.8, **kw)
    assert np.allclose(f.heights[::2, ::2], c.heights, atol=1e-12 * 1e-6)
    assert rms_height(c) == pytest.approx(rms_height(f), rel=1e-12)
    other = self_affine(64, L, 0.8, **{**kw, "seed": 12})
    assert not np.allclose(other.heights, c.heights)


def test_spectrum_shape():
    q = np.array([0.0, 1.0, 2.0, 4.0, 8.0, 9.0])
    C = self_affine_psd(q, 0.5, rolloff=2.0, cutoff=8.0)
    assert C[0] == 0 and C[1] == 1 and C[2] == 1 and C[5] == 0
    assert C[4] / C[3] == pytest.approx(2.0 ** -3)


@pytest.mark.parametrize("kw,match", [
    ({"hurst": 1.2}, "hurst"), ({"hurst": 0.0}, "hurst"),
    ({"rms_slope": 0.1}, "exactly one"), ({"rms_height": None}, "exactly one"),
    ({"cutoff": L / 100}, "two pixels"), ({"rolloff": 2 * L}, "rolloff"),
    ({"cutoff": L / 2, "rolloff": L / 4}, "cutoff"), ({"rms_height": -1.0}, "rms_height"),
    ({"amplitudes": "uniform"}, "amplitudes"), ({"n": 4}, "n = 4")])
def test_bad_synthesis_input_is_refused(kw, match):
    args = {"n": 64, "length": L, "hurst": 0.8, "rms_height": 1e-6, **kw}
    with pytest.raises(RoughnessError, match=match):
        self_affine(**args)


def _surface():
    return self_affine(32, L, 0.8, rms_height=1e-6, cutoff=L / 8, seed=2)


def test_reader_round_trips(tmp_path):
    t = _surface()
    h_um = t.heights * 1e6
    np.save(tmp_path / "a.npy", h_um)
    np.savez(tmp_path / "b.npz", heights=h_um, pixel_size=L / 32 * 1e6)
    np.savetxt(tmp_path / "c.csv", h_um, delimiter=",", header="heights in um")
    np.savetxt(tmp_path / "d.txt", h_um)
    for name, kw in (("a.npy", {"pixel_size": L / 32 * 1e6}), ("b.npz", {}),
                     ("c.csv", {"pixel_size": L / 32 * 1e6}),
                     ("d.txt", {"pixel_size": (L / 32 * 1e6, L / 32 * 1e6)})):
        r = read_topography(tmp_path / name, unit="um", periodic=True, detrend_mode="mean",
                            **kw)
        assert r.pixel == pytest.approx((L / 32, L / 32), rel=1e-12)
        assert np.allclose(r.heights, t.heights - t.heights.mean(), atol=1e-15), name
    # a tilted measurement is levelled by default
    X, Y = np.meshgrid(np.arange(32), np.arange(32), indexing="ij")
    np.save(tmp_path / "tilt.npy", h_um + 0.3 * X - 0.1 * Y + 5.0)
    r = read_topography(tmp_path / "tilt.npy", pixel_size=L / 32 * 1e6, unit="um")
    flat = read_topography(tmp_path / "a.npy", pixel_size=L / 32 * 1e6, unit="um")
    assert np.allclose(r.heights, flat.heights, atol=1e-9 * rms_height(t))
    assert rms_height(r) <= rms_height(t) * (1 + 1e-9)


@pytest.mark.parametrize("content,kw,match", [
    ("1 2 3\n4 x 6\n", {"pixel_size": 1.0}, r"line 2, column 2: 'x'"),
    ("1 2 3\n4 5\n", {"pixel_size": 1.0}, "line 2 has 2 values, line 1 has 3"),
    ("# only a comment\n", {"pixel_size": 1.0}, "no numbers"),
    ("1 2 3 4\n" * 4, {}, "pixel_size is missing"),
    ("1 2 3 4\n" * 4, {"pixel_size": -1.0}, "pixel_size"),
    ("1 2 3 4\n" * 4, {"pixel_size": 1.0, "unit": "inch"}, "unit"),
    ("1 2\n3 4\n", {"pixel_size": 1.0}, "at least 4 x 4"),
    ("1 2 3 nan\n" + "1 2 3 4\n" * 3, {"pixel_size": 1.0},
     r"non-finite.*row 1, column 4 \(counting from 1\)")])
def test_reader_refuses_bad_files_naming_the_place(tmp_path, content, kw, match):
    f = tmp_path / "h.txt"
    f.write_text(content)
    with pytest.raises(RoughnessError, match=match) as exc:
        read_topography(f, **kw)
    assert str(f) in str(exc.value)
    assert isinstance(exc.value, InputError)


def test_reader_refuses_unknown_suffix_and_missing_file(tmp_path):
    f = tmp_path / "h.sur"
    f.write_bytes(b"\x00\x01")
    with pytest.raises(RoughnessError, match="suffix '.sur'"):
        read_topography(f, pixel_size=1.0)
    with pytest.raises(RoughnessError, match="no such file"):
        read_topography(tmp_path / "none.npy", pixel_size=1.0)
    np.savez(tmp_path / "x.npz", z=np.zeros((8, 8)))
    with pytest.raises(RoughnessError, match="no array 'heights'"):
        read_topography(tmp_path / "x.npz", pixel_size=1.0)


def test_topography_checks_its_grid():
    with pytest.raises(RoughnessError, match="2D grid"):
        Topography(np.zeros(16), 1.0)
    with pytest.raises(RoughnessError, match="pixel"):
        Topography(np.zeros((8, 8)), 0.0)
    t = Topography(np.ones((8, 4)), (1.0, 2.0))
    assert t.size == (8.0, 8.0) and t.pixel_area == 2.0
    X, Y = t.coordinates()
    assert X.mean() == pytest.approx(0.0) and Y.mean() == pytest.approx(0.0)
    assert rms_height(t) == 0.0 and rms_slope(t) == 0.0
