"""Issue 17's examples for the command line and the claims: exit codes, strict JSON, real
booleans, claims that fail on NaN data, and the profile from the environment."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from fusioncenter import figures
from fusioncenter.cli import dumps, jsonable, main
from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Claim, nonfinite_keys


def _strict_loads(text: str):
    def no_constant(name):
        raise AssertionError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=no_constant)


@pytest.fixture
def probe(monkeypatch):
    """A cheap registered entry whose data hold NumPy scalars and non-finite values."""
    from fusioncenter.figures import registry

    figures.ids()
    seen = {}

    def compute(profile, seed, **over):
        seen["profile"] = profile
        return {"nan": np.float64("nan"), "inf": np.inf, "f32": np.float32(1.5),
                "arr": np.array([1.0, -np.inf]), "i": np.int64(3), "b": np.bool_(True),
                "k": over.get("k", 2), "text": "x"}

    def checks(data):
        return [Claim("general", True), Claim("the paper's number", True, paper_specific=True)]

    entry = figures.Entry(id="book-cli-probe", paper="book", kind="figure", caption="probe",
                          chapter="book/howto", compute=compute, checks=checks,
                          plot=lambda d: None, status="reproduced",
                          nonfinite_ok=("nan", "inf", "arr"),
                          settable=(Parameter("k", "int", "a count", 2, minimum=1),
                                    Parameter("N", "int", "sensors", 2, minimum=1, model=True)))
    monkeypatch.setitem(registry.REGISTRY, entry.id, entry)
    return seen


# ------------------------------------------------------------------------------ claims
def test_claim_passed_must_be_a_real_bool():
    with pytest.raises(TypeError, match="passed must be a bool"):
        Claim("x", "False")
    with pytest.raises(TypeError, match="passed must be a bool"):
        Claim("x", 1)
    with pytest.raises(TypeError, match="passed must be a bool"):
        Claim("x", np.array([True]))
    c = Claim("x", np.bool_(False))
    assert c.passed is False and not c
    assert Claim("y", True)


def _nanify(value):
    """Every float of ``value`` (arrays, scalars, nested lists and dicts) replaced by NaN."""
    if isinstance(value, dict):
        return {k: _nanify(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(_nanify(v) for v in value)
    if isinstance(value, np.ndarray) and value.dtype.kind in "fc":
        return np.full_like(value, np.nan)
    if isinstance(value, float | np.floating):
        return float("nan")
    return value


NAN_ENTRIES = [("background-riccati", {}), ("background-kf-montecarlo", {}),
               ("dey2009-fig1", {"paths": 2100, "grid_paths": 100}), ("leong2011-fig1", {}),
               ("mo2015-rate", {})]


@pytest.mark.parametrize(("entry_id", "over"), NAN_ENTRIES)
def test_every_claim_fails_on_all_nan_data(entry_id, over):
    e = figures.get(entry_id)
    data = e.run_compute("fast", **over)
    assert not nonfinite_keys(data, e.nonfinite_ok)  # the real data are finite
    claims = e.run_checks(_nanify(data))
    assert claims and not any(claims), [c.name for c in claims if c]
    assert all("non-finite" in c.detail for c in claims)


def test_nonfinite_keys_looks_inside_containers():
    data = {"a": 1.0, "b": [1.0, float("inf")], "c": {"d": np.array([np.nan])}, "e": "nan",
            "f": np.arange(3), "g": np.array(["x"], dtype=object)}
    assert nonfinite_keys(data) == ["b", "c"]
    assert nonfinite_keys(data, allowed=("b",)) == ["c"]


# ------------------------------------------------------------------------------ JSON
def test_strict_json_encodes_nonfinite_and_numpy_scalars_one_way():
    assert jsonable({"a": np.float32(2.5), "b": np.float64("nan"), "c": [np.inf, -np.inf],
                     "d": np.int8(3), "e": np.bool_(True), "f": 1 + 2j}) == {
        "a": 2.5, "b": "NaN", "c": ["Infinity", "-Infinity"], "d": 3, "e": True,
        "f": [1.0, 2.0]}
    assert _strict_loads(dumps({"x": np.array([np.nan, 1.0])})) == {"x": ["NaN", 1.0]}


def test_cli_json_is_strict_and_records_the_run(probe, capsys):
    assert main(["compute", "book-cli-probe", "--json", "--set", "k=7"]) == 0
    out = _strict_loads(capsys.readouterr().out)
    assert out["nan"] == "NaN" and out["inf"] == "Infinity" and out["arr"] == [1.0, "-Infinity"]
    assert out["f32"] == 1.5 and out["i"] == 3 and out["b"] is True and out["k"] == 7
    assert out["_run"] == {"id": "book-cli-probe", "profile": "fast", "seed": 20260101,
                           "executor": "serial", "parameters": {"k": 7, "N": 2},
                           "overridden": ["k"]}


# ------------------------------------------------------------------------------ exit codes
def _one_line_error(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def test_output_to_a_directory_or_unwritable_path_exits_3(probe, tmp_path, capsys):
    assert main(["compute", "book-cli-probe", "--csv", str(tmp_path)]) == 3
    assert "is a directory" in _one_line_error(capsys.readouterr().err)
    assert main(["compute", "book-cli-probe", "--csv", str(tmp_path / "no" / "x.csv")]) == 3
    assert "does not exist" in _one_line_error(capsys.readouterr().err)
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert main(["plot", "book-cli-probe", "-o", str(blocker)]) == 3
    _one_line_error(capsys.readouterr().err)
    assert main(["compute", "book-cli-probe", "--csv", "/proc/self/nope.csv"]) == 3
    _one_line_error(capsys.readouterr().err)


def _cache_file(tmp_path):
    files = list(tmp_path.glob("book-cli-probe.fast.20260101.npz"))
    assert len(files) == 1, sorted(p.name for p in tmp_path.iterdir())
    return files[0]


def _rewrite(path, edit_meta=None, edit_arrays=None):
    """Rewrite a cache file with its record or arrays changed, keeping the stored digest."""
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k].copy() for k in z.files}
    meta = json.loads(arrays["meta"].tobytes())
    if edit_meta:
        edit_meta(meta)
    if edit_arrays:
        edit_arrays(arrays)
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with path.open("wb") as fh:
        np.savez(fh, **arrays)


def test_compute_cache_never_serves_a_tampered_file(probe, tmp_path, monkeypatch, capsys):
    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    assert _strict_loads(capsys.readouterr().out)["k"] == 2
    path = _cache_file(tmp_path)
    probe.clear()
    assert main(["compute", "book-cli-probe", "--json"]) == 0  # served: no compute
    assert probe == {} and _strict_loads(capsys.readouterr().out)["k"] == 2

    def number(meta):  # a hand-edited number: k = 2 becomes 7
        ks = [k.get("v") if isinstance(k, dict) else k for k in meta["tree"]["k"]]
        meta["tree"]["v"][ks.index("k")]["v"] = "7"

    def array(arrays):  # a changed array element
        for name, arr in arrays.items():
            if name != "meta" and arr.dtype.kind == "f" and arr.size == 2:
                arr[0] = 123.0

    for edit in ({"edit_meta": number}, {"edit_arrays": array}):
        _rewrite(path, **edit)
        probe.clear()
        assert main(["compute", "book-cli-probe", "--json"]) == 0
        out = capsys.readouterr()
        data = _strict_loads(out.out)
        assert data["k"] == 2 and data["arr"] == [1.0, "-Infinity"]
        assert probe == {"profile": "fast"}, "the tampered file was served, not recomputed"
        assert f"compute cache file {path} not used" in out.err
        assert "integrity check failed" in out.err


class _Payload:
    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        import os

        return (os.system, (f"touch {self.marker}",))


def test_compute_cache_never_runs_a_planted_pickle(probe, tmp_path, monkeypatch, capsys):
    import pickle

    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    marker = tmp_path / "owned"
    payload = pickle.dumps({"k": _Payload(marker)})
    assert pickle.loads(pickle.dumps(_Payload(tmp_path / "check"))) == 0  # it does run code
    assert (tmp_path / "check").exists()
    for name in ("book-cli-probe.fast.20260101.npz", "book-cli-probe.fast.20260101.pickle"):
        (tmp_path / name).write_bytes(payload)
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    out = capsys.readouterr()
    assert not marker.exists(), "loading the cache ran the planted code"
    assert _strict_loads(out.out)["k"] == 2 and probe == {"profile": "fast"}
    assert "not a compute-cache file" in out.err


def test_compute_cache_holding_a_non_dict_is_recomputed(probe, tmp_path, monkeypatch, capsys):
    from fusioncenter import _cache

    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    capsys.readouterr()
    path = _cache_file(tmp_path)
    key = {"id": "book-cli-probe", "profile": "fast", "seed": 20260101, "overrides": []}
    assert _cache.load(path, key)[0]  # the key the registry uses
    _cache.dump(path, [1, 2, 3], key)  # a sound file of the right key, but no dict
    probe.clear()
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    out = capsys.readouterr()
    assert probe == {"profile": "fast"} and "holds a list, not a dict" in out.err


def test_compute_cache_is_keyed_by_the_library_source(probe, tmp_path, monkeypatch, capsys):
    from fusioncenter import _cache

    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    probe.clear()
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    assert probe == {}  # same library: served
    monkeypatch.setattr(_cache, "fingerprint", lambda: "0" * 64)  # the library's code changed
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    assert probe == {"profile": "fast"}, "a result of another library version was served"
    probe.clear()
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    assert probe == {}  # rewritten under the new fingerprint
    assert "not used" not in capsys.readouterr().err  # stale is not tampered: no warning


def test_fingerprint_follows_the_source(tmp_path, monkeypatch):
    from fusioncenter import _cache

    a = _cache.fingerprint()
    assert len(a) == 64 and a == _cache.fingerprint()
    src = tmp_path / "fusioncenter"
    src.mkdir()
    (src / "m.py").write_text("x = 1\n")
    monkeypatch.setattr(_cache, "__file__", str(src / "_cache.py"))
    _cache.fingerprint.cache_clear()
    try:
        b = _cache.fingerprint()
        (src / "m.py").write_text("x = 2\n")
        _cache.fingerprint.cache_clear()
        assert _cache.fingerprint() not in (a, b)
    finally:
        monkeypatch.undo()
        _cache.fingerprint.cache_clear()
    assert _cache.fingerprint() == a


def test_unreadable_compute_cache_exits_3_naming_the_file(probe, tmp_path, monkeypatch,
                                                         capsys):
    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    (tmp_path / "book-cli-probe.fast.20260101.npz").mkdir()  # exists, cannot be read
    assert main(["compute", "book-cli-probe", "--json"]) == 3
    line = _one_line_error(capsys.readouterr().err)
    assert "unreadable" in line and "book-cli-probe.fast.20260101.npz" in line
    with pytest.raises(figures.registry.ComputeCacheError, match="delete it"):
        figures.get("book-cli-probe").run_compute("fast")


@pytest.mark.parametrize("argv", [
    ["compute", "book-cli-probe", "--json", "--set", "k=0"],
    ["compute", "book-cli-probe", "--json", "--set", "zz=1"],
    ["compute", "book-cli-probe", "--json", "--set", "k"],
    ["compute", "book-cli-probe", "--json", "--executor", "gpu"],
    ["verify", "zheng2014-table1", "--set", "N=1.5"],
])
def test_bad_values_exit_2_with_one_line(probe, argv, capsys):
    assert main(argv) == 2
    _one_line_error(capsys.readouterr().err)


def test_unknown_set_key_lists_the_valid_ones(probe, capsys):
    assert main(["compute", "zheng2014-table1", "--json", "--set", "trial=5"]) == 2
    assert "valid keys: N, particles, trials" in capsys.readouterr().err


def test_verify_skips_paper_specific_claims_under_a_model_override(probe, capsys):
    assert main(["verify", "book-cli-probe", "--set", "k=3"]) == 0
    assert "2 passed, 0 failed" in capsys.readouterr().out
    assert main(["verify", "book-cli-probe", "--set", "N=5"]) == 0
    out = capsys.readouterr().out
    assert "SKIP  the paper's number  [paper-specific: N overridden]" in out
    assert "1 passed, 0 failed, 1 skipped (paper-specific)" in out


def test_claim_failure_exits_1(probe, monkeypatch, capsys):
    entry = figures.get("book-cli-probe")
    monkeypatch.setattr(entry, "checks", lambda d: [Claim("wrong", False)])
    assert main(["verify", "book-cli-probe"]) == 1
    assert "FAIL  wrong" in capsys.readouterr().out


def test_cli_honours_the_profile_variable_and_flags_win(probe, monkeypatch, capsys):
    monkeypatch.setenv("FUSIONCENTER_PROFILE", "paper")
    monkeypatch.setenv("FUSIONCENTER_EXECUTOR", "serial")
    assert main(["compute", "book-cli-probe", "--json"]) == 0
    assert probe["profile"] == "paper"
    assert _strict_loads(capsys.readouterr().out)["_run"]["profile"] == "paper"
    assert main(["compute", "book-cli-probe", "--json", "--profile", "fast"]) == 0
    assert probe["profile"] == "fast"
    monkeypatch.setenv("FUSIONCENTER_PROFILE", "huge")
    assert main(["compute", "book-cli-probe", "--json"]) == 2
    assert "FUSIONCENTER_PROFILE" in capsys.readouterr().err


def test_params_lists_the_settable_parameters(capsys):
    assert main(["params", "zheng2014-table1"]) == 0
    out = capsys.readouterr().out
    assert "trials (int" in out and "N (int" in out and "[changes the paper's setting]" in out


def test_module_entry_point_exit_codes():
    run = [sys.executable, "-m", "fusioncenter"]
    p = subprocess.run([*run, "compute", "background-riccati", "--json", "--set", "x=1"],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    p = subprocess.run([*run, "compute", "background-riccati", "--json"], capture_output=True,
                       text=True)
    assert p.returncode == 0 and math.isfinite(_strict_loads(p.stdout)["p_scalar"][0])


# ------------------------------------------------------------------ issue 30: the command line
def test_csv_dash_writes_to_standard_output(probe, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["compute", "book-cli-probe", "--csv", "-"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("name,index,value\n_run,id,book-cli-probe\n")
    assert "k,,2\n" in out and "\r" not in out
    assert not (tmp_path / "-").exists()


def test_a_repeated_set_key_is_an_error(probe, capsys):
    assert main(["compute", "book-cli-probe", "--json", "--set", "k=3", "--set", "k=4"]) == 2
    line = _one_line_error(capsys.readouterr().err)
    assert "--set k given twice" in line and probe == {}


def test_numbers_read_python_syntax_for_both_kinds():
    n = Parameter("n", "int", "a count", 2, minimum=1)
    x = Parameter("x", "float", "a level", 1.0)
    assert n.parse("4_00") == 400 and x.parse("4_00") == 400.0
    assert n.parse("1e3") == 1000 and x.parse("1e3") == 1000.0
    assert n.parse("2.5e1") == 25 and n.parse("1e30") == 10**30  # exact, no float rounding
    for bad in ("1.5", "1e-3", "inf", "nan", "1e", "4__0", "0x10"):
        with pytest.raises(ValueError, match="parameter n: expected an integer"):
            n.parse(bad)


def test_params_shows_every_bound_and_bounds_are_checked_before_computing(capsys):
    assert main(["params", "zheng2014-fig1"]) == 0
    out = capsys.readouterr().out
    assert "l (float, 0 < l <= N;" in out and "N (int, 1 <= N <= 64;" in out
    assert "trials (int, 2 <= trials;" in out and "default fast 200, paper 5000" in out
    assert main(["params", "zheng2014-fig3"]) == 0
    assert "2 <= trials_heavy <= trials, a multiple of 256 below trials;" in \
        capsys.readouterr().out
    assert main(["compute", "zheng2014-fig3", "--json", "--set", "trials=1000", "--set",
                 "trials_heavy=300"]) == 2
    err = capsys.readouterr().err
    assert "trials_heavy: below trials (1000) it must be a multiple of 256, got 300" in \
        _one_line_error(err) and "computing" not in err
    for value, msg in (("5", "parameter l: must be <= N (2), got 5.0"),
                       ("0", "parameter l: must be > 0, got 0.0")):
        assert main(["compute", "zheng2014-fig1", "--json", "--set", f"l={value}"]) == 2
        err = capsys.readouterr().err
        assert msg in _one_line_error(err) and "computing" not in err
    assert main(["compute", "zheng2014-fig1", "--json", "--set", "N=6", "--set", "l=5",
                 "--set", "trials=-1"]) == 2  # l <= N holds; trials does not
    assert "trials: must be >= 2" in capsys.readouterr().err


def test_an_absurd_size_is_refused_before_allocating(capsys):
    import time

    t0 = time.monotonic()
    assert main(["compute", "zheng2014-fig1", "--json", "--set", "particles=1000000000"]) == 2
    line = _one_line_error(capsys.readouterr().err)
    assert "particles = 1000000000" in line and "GiB of memory" in line and "available" in line
    assert main(["compute", "background-kf-montecarlo", "--json", "--set",
                 "trials=1000000000"]) == 2
    line = _one_line_error(capsys.readouterr().err)
    assert "n_trials = 1000000000" in line and "GiB of memory" in line
    assert time.monotonic() - t0 < 60


def test_the_monte_carlo_memory_guard_names_the_trials(monkeypatch):
    from fusioncenter import montecarlo

    calls = []

    def fn(rng, n):
        calls.append(n)
        return rng.standard_normal((n, 4))

    monkeypatch.setattr(montecarlo, "available_memory", lambda: 2**30)
    with pytest.raises(ValueError, match=r"n_trials = 100000000: .* about 5\.96 GiB .* "
                                         r"1 GiB available"):
        montecarlo.simulate(fn, 100_000_000, 1)
    assert calls == [256]  # one block ran, nothing else was allocated
    with pytest.raises(ValueError, match="random streams"):  # before the seeds are made
        montecarlo.simulate(fn, 10**13, 1)
    assert calls == [256]
    assert montecarlo.simulate(fn, 1000, 1).samples.shape == (1000, 4)  # fits: runs


@pytest.mark.parametrize("exc, code, text", [
    (MemoryError("Unable to allocate 14.9 GiB"), 3, "out of memory while computing"),
    (OSError("scheduler gone"), 3, "scheduler gone"),
    (ZeroDivisionError("a bug"), 4, "internal error (ZeroDivisionError)"),
    (__import__("concurrent.futures.process").futures.process.BrokenProcessPool(
        "A process in the process pool was terminated abruptly"), 3, "terminated abruptly"),
])
def test_failures_during_a_run_exit_with_the_table_code(probe, monkeypatch, capsys, exc,
                                                        code, text):
    entry = figures.get("book-cli-probe")

    def compute(profile, seed, **over):
        raise exc

    monkeypatch.setattr(entry, "compute", compute)
    assert main(["compute", "book-cli-probe", "--json"]) == code
    err = capsys.readouterr().err
    if code == 4:
        assert "Traceback" in err and err.rstrip().splitlines()[-1].startswith("error: ")
        assert text in err
    else:
        assert text in _one_line_error(err)


def test_a_lost_dask_scheduler_exits_3(probe, monkeypatch, capsys):
    from concurrent.futures import CancelledError

    distributed = pytest.importorskip("distributed")
    entry = figures.get("book-cli-probe")
    for exc in (distributed.comm.core.CommClosedError("in <TCP (closed)>: Stream is closed"),
                CancelledError("lost")):
        def compute(profile, seed, exc=exc, **over):
            raise exc

        monkeypatch.setattr(entry, "compute", compute)
        assert main(["compute", "book-cli-probe", "--json"]) == 3
        assert type(exc).__name__ in _one_line_error(capsys.readouterr().err)


def test_help_documents_the_cache_and_the_exit_codes():
    for argv in (["--help"], ["compute", "--help"]):
        p = subprocess.run([sys.executable, "-m", "fusioncenter", *argv], capture_output=True,
                           text=True)
        assert p.returncode == 0
        assert "FUSIONCENTER_COMPUTE_CACHE" in p.stdout and "143 terminated" in p.stdout


def test_list_params_and_a_misspelt_id_import_no_figure_module():
    from fusioncenter.figures import registry

    registry.build_index()  # the index is current (written again if the source changed)
    code = ("import sys; from fusioncenter.cli import main\n"
            "for argv in (['list'], ['list', '--json'], ['params', 'zheng2014-table1'],\n"
            "             ['params', 'zheng2014-tabel1']):\n"
            "    print(main(argv), file=sys.stderr)\n"
            "print(sorted(m for m in sys.modules if m.startswith(('numpy', 'matplotlib',\n"
            "      'fusioncenter.figures.'))), file=sys.stderr)")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    lines = p.stderr.strip().splitlines()
    assert lines[-1] == "['fusioncenter.figures._index']", p.stderr
    assert [ln for ln in lines if ln in "0 2"] == ["0", "0", "0", "2"]
    assert "did you mean zheng2014-table1" in p.stderr


def test_the_index_matches_the_registry():
    from fusioncenter import _cache
    from fusioncenter.figures import _index as index
    from fusioncenter.figures import registry

    rows = registry.build_index(write=False)["entries"]
    assert [r["id"] for r in rows] == figures.ids()
    stored = json.loads(index.PATH.read_text())
    if stored["source"] == _cache.fingerprint():  # a current index holds these rows
        assert index.load() == stored["entries"] == rows
    for r in rows:
        e = figures.get(r["id"])
        assert r["settable_lines"] == e.settable_lines()
        assert {k: v for k, v in r.items() if k not in ("module", "settable_lines")} == \
            json.loads(json.dumps(e.summary()))


def test_a_stale_index_is_not_used(monkeypatch):
    from fusioncenter import _cache
    from fusioncenter.figures import _index as index

    monkeypatch.setattr(index, "_CURRENT", [])
    monkeypatch.setattr(_cache, "fingerprint", lambda: "changed source")
    assert index.load() is None and index.find("dey2009-fig1") is None


def test_compute_imports_only_the_module_of_its_entry():
    from fusioncenter.figures import registry

    registry.build_index()  # current
    code = ("import sys; from fusioncenter import figures\n"
            "e = figures.get(sys.argv[1]); assert e.id == sys.argv[1]\n"
            "print(sorted(m.split('.')[2] for m in sys.modules\n"
            "             if m.startswith('fusioncenter.figures.') and m.count('.') >= 3))")
    for entry_id, part in (("dey2009-fig1", "dey2009"), ("zheng2014-table1", "zheng2014")):
        p = subprocess.run([sys.executable, "-c", code, entry_id], capture_output=True,
                           text=True)
        assert p.returncode == 0, p.stderr
        assert set(eval(p.stdout)) == {part}, p.stdout  # noqa: S307 (our own list)
