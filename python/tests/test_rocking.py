"""The Python package against the command line: the same inputs give the
same JSON, float for float (both print serde's shortest round-trip text,
read back exactly). Run by tests/python.rs, which sets ROCKING_BIN (the
`rocking` binary built with the package) and runs from the repository root.
"""

import json
import math
import re
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import polars as pl
import pytest

import rocking

ROOT = Path(os.environ.get("ROCKING_ROOT", Path(__file__).resolve().parents[2]))
BIN = os.environ.get("ROCKING_BIN", str(ROOT / "target" / "release" / "rocking"))
FAR = ROOT / "records" / "fema-p695" / "far-field"
KOBE = FAR / "RSN1111_KOBE_NIS000.AT2"
HAZARD = ROOT / "records" / "hazard" / "synthetic-site.csv"


def cli(*args):
    out = subprocess.run([BIN, *map(str, args)], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out.stdout


def in_python_words(text):
    """A message as Python's answers word it (the guide's rule): a
    command-line option as its keyword, `--auto-tol` as `auto_tol`, a switch
    `--direct` as `direct=True`, `--from` as `source`."""

    def keyword(m):
        name = m.group(1)
        if name in ("direct", "vector"):
            return name + "=True"
        return "source" if name == "from" else name.replace("-", "_")

    return re.sub(r"(?<![\w-])--([a-z][a-z0-9-]*)", keyword, text)


def worded(v):
    """The command's JSON with every `warnings` list in Python's words."""
    if isinstance(v, dict):
        return {
            k: [in_python_words(w) if isinstance(w, str) else worded(w) for w in x]
            if k == "warnings" and isinstance(x, list)
            else worded(x)
            for k, x in v.items()
        }
    if isinstance(v, list):
        return [worded(x) for x in v]
    return v


def cli_json(*args):
    return worded(json.loads(cli(*args, "--json")))


def cli_lines(*args):
    return [worded(json.loads(line)) for line in cli(*args, "--json").splitlines()]


def same(a, b, skip=()):
    """Equal dicts, floats to the bit (NaN-free JSON: == is bitwise here)."""
    assert set(a) == set(b), set(a) ^ set(b)
    for k in a:
        if k in skip:
            continue
        assert a[k] == b[k], (k, a[k], b[k])


def plain_at2(path):
    """An AT2 reader of its own (the bundled files' layout): skip four lines, read every token."""
    lines = Path(path).read_text().splitlines()
    header = lines[3]
    dt = float(header.split("DT=")[1].split()[0])
    return np.array([float(t) for line in lines[4:] for t in line.split()]), dt


def test_read_at2_is_the_file():
    acc, dt = rocking.read_at2(KOBE)
    ref, ref_dt = plain_at2(KOBE)
    assert acc.dtype == np.float64 and acc.ndim == 1
    assert dt == ref_dt == 0.01
    assert np.array_equal(acc, ref)


@pytest.mark.parametrize(
    "py, args",
    [
        (dict(p=2.0, eps=0.7), ["--p", "2", "--eps", "0.7"]),
        (
            dict(b=0.2, h=0.9, eps="housner", model="auto"),
            ["--b", "0.2", "--h", "0.9", "--eps", "housner", "--model", "auto"],
        ),
        (
            dict(width=0.6, height=2.0, eps=0.8, model="nonlinear", integrator="dp5", rtol=1e-9),
            ["--width", "0.6", "--height", "2", "--eps", "0.8", "--model", "nonlinear",
             "--integrator", "dp5", "--rtol", "1e-9"],
        ),
        (
            dict(p=1.5, eps=0.9, alpha=0.15, overturn="escape", tol=1e-3, levels=80, eta_min=0.01,
                 spacing="linear"),
            ["--p", "1.5", "--eps", "0.9", "--alpha", "0.15", "--overturn", "escape", "--tol",
             "1e-3", "--levels", "80", "--eta-min", "0.01", "--spacing", "linear"],
        ),
        (
            dict(b=0.3, h=1.0, eps=0.75, floor=[(0.5, 0.05, 1.3), (0.2, 0.05, -0.3)], mu=0.4),
            ["--b", "0.3", "--h", "1", "--eps", "0.75", "--floor", "0.5,0.05,1.3", "--floor",
             "0.2,0.05,-0.3", "--mu", "0.4"],
        ),
    ],
)
def test_capacity_is_the_commands(py, args):
    ours = rocking.capacity(KOBE, **py)
    theirs = cli_json("capacity", "--record", KOBE, *args)
    same(ours, theirs)
    # The same record as an array: the same capacity (its id aside).
    acc, dt = rocking.read_at2(KOBE)
    from_array = rocking.capacity(acc, dt, record_id="RSN1111_KOBE_NIS000", **py)
    same(from_array, theirs)


def test_capacity_of_several_blocks_is_every_one():
    # p × eps gave four capacities, of which the first alone came back.
    ours = rocking.capacity(KOBE, p=[1.0, 2.0], eps=[0.7, 0.9])
    theirs = cli_lines("capacity", "--record", KOBE, "--p", "1,2", "--eps", "0.7,0.9")
    assert isinstance(ours, list) and len(ours) == len(theirs) == 4
    for a, b in zip(ours, theirs):
        same(a, b)


def test_capacity_of_a_folder_is_every_record(tmp_path):
    # A folder of records gave its first record's capacity alone, the rest
    # dropped without a word. Each capacity is that record's alone.
    kobe = [KOBE, FAR / "RSN1111_KOBE_NIS090.AT2"]
    folder = tmp_path / "kobe"
    folder.mkdir()
    for f in kobe:
        (folder / f.name).write_bytes(f.read_bytes())
    ours = rocking.capacity(folder, p=2.0, eps=0.7)
    assert isinstance(ours, list) and len(ours) == 2
    assert sorted(c["record_id"] for c in ours) == sorted(f.stem for f in kobe)
    for c in ours:
        same(c, rocking.capacity(folder / (c["record_id"] + ".AT2"), p=2.0, eps=0.7))
    # A folder of one record is still a folder: a list.
    (folder / kobe[1].name).unlink()
    one = rocking.capacity(folder, p=2.0, eps=0.7)
    assert isinstance(one, list) and len(one) == 1


def test_keywords_are_refused_by_their_python_names(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    # An empty folder wrote the export into the current directory.
    with pytest.raises(ValueError, match="give out"):
        rocking.export("", format="pelicun", b=0.2, h=0.9)
    assert list(tmp_path.iterdir()) == []
    # A NaN angle reached the record's reader, which blamed the record.
    with pytest.raises(ValueError, match="angle=NaN: an angle in degrees"):
        rocking.capacity(KOBE, pair=FAR / "RSN1111_KOBE_NIS090.AT2", angle=float("nan"),
                         p=2.0, eps=0.7)
    # True/false keywords went by truth: direct="no" ran the records.
    for no in ["no", 0, 2.5]:
        with pytest.raises(ValueError, match="True or False for `direct`"):
            rocking.fragility(0.2, 0.9, pga=[0.3], direct=no)
    assert rocking.fragility(0.2, 0.9, pga=[0.3], direct=np.bool_(False))["fit"] == "regression"
    # An angle without its pair was ignored.
    with pytest.raises(ValueError, match="angle: give pair too"):
        rocking.capacity(KOBE, angle=30, p=2.0, eps=0.7)
    # A negative α gave a negative PGA at overturning.
    with pytest.raises(ValueError, match=r"alpha=-0.1: the slenderness α is an angle"):
        rocking.capacity(KOBE, p=2.0, eps=0.7, alpha=-0.1)


def test_messages_name_the_keywords_python_wrote():
    def refusal(f):
        with pytest.raises(ValueError) as e:
            f()
        text = str(e.value)
        assert "--" not in text, text
        return text

    # The work's own messages named the command line's options.
    assert refusal(lambda: rocking.risk(HAZARD, b=0.2, h=0.9, years=-1)).startswith("years -1")
    assert "b and h must be positive" in refusal(lambda: rocking.risk(HAZARD, b=-0.2, h=0.9))
    assert "tree takes a TOML file" in refusal(lambda: rocking.risk(HAZARD, b=0.2, h=0.9, tree="nope"))
    # A value of the wrong type: "did not match any variant of untagged enum".
    assert refusal(lambda: rocking.fragility(0.2, 0.9, at="abc")).startswith("at: give a number")
    # A warning in an answer: the regression at this α asks for the records' runs.
    w = rocking.fragility(0.2, 0.9, pga=[0.3])["warnings"]
    assert any("use direct=True" in x for x in w), w
    assert not any("--" in x for x in w), w
    # An answer's warnings are also Python's, as the command prints them:
    # the block slides before it rocks (μ = 0.1 < b/h = 0.22, a statics
    # fact), said once though the answer holds it in two places.
    with pytest.warns(UserWarning) as said:
        f = rocking.fragility(0.2, 0.9, pga=[0.3], mu=0.1)
    texts = [str(x.message) for x in said]
    # Attributed to this file, the caller's, however deep in the answer.
    assert all(x.filename == __file__ for x in said), [x.filename for x in said]
    assert any("slides before it rocks" in t for t in texts), texts
    assert sorted(set(texts)) == sorted(texts), texts
    assert set(texts) <= set(f["warnings"]) | {w for s in f.get("states", []) for w in s.get("warnings", [])}
    # A hazard file declares its IM: hazard_im was ignored.
    assert "hazard_im='pgv'" in refusal(lambda: rocking.risk(HAZARD, b=0.2, h=0.9, hazard_im="pgv"))


def test_a_block_takes_numpy_arrays_as_lists():
    arrays = rocking.Block(b=np.array([0.2, 0.3]), h=np.array([0.9, 1.2]), eps=np.float64(0.8))
    lists = rocking.Block(b=[0.2, 0.3], h=[0.9, 1.2], eps=0.8)
    assert len(arrays) == 2 and arrays == lists
    a = rocking.capacities([KOBE], [arrays])
    b = rocking.capacities([KOBE], [lists])
    assert a.equals(b)


def test_simulate_is_the_commands():
    for py, args in [
        (dict(p=2.0, eps=0.7, eta=0.3), ["--p", "2", "--eps", "0.7", "--eta", "0.3"]),
        (dict(b=0.2, h=1.0, eps=0.9, pga=0.4, model="auto"),
         ["--b", "0.2", "--h", "1", "--eps", "0.9", "--pga", "0.4", "--model", "auto"]),
        (dict(b=0.2, h=1.0, eps=0.9, pga=0.1, floor=[(0.5, 0.05, 1.3)]),
         ["--b", "0.2", "--h", "1", "--eps", "0.9", "--pga", "0.1", "--floor", "0.5,0.05,1.3"]),
        # A block that slides: its slide and its time in each mode.
        (dict(b=0.3, h=0.5, eps=0.8, pga=0.6, model="slide-rock", mu=0.3, mu_k=0.25),
         ["--b", "0.3", "--h", "0.5", "--eps", "0.8", "--pga", "0.6", "--model", "slide-rock",
          "--mu", "0.3", "--mu-k", "0.25"]),
    ]:
        same(rocking.simulate(KOBE, **py), cli_json("simulate", "--record", KOBE, *args))


def test_a_batch_is_the_commands_batch(tmp_path):
    blocks = [dict(p=2.0, eps=0.7), rocking.Block(b=0.15, h=1.0, eps=0.85, model="auto")]
    table = rocking.capacities(FAR, blocks)
    # The command's own table of the same batch: the same rows, the same
    # Arrow types (the table crosses as Parquet, never as JSON text).
    out = tmp_path / "caps.parquet"
    cli("capacity", "--record", FAR, "--p", "2", "--eps", "0.7", "--out", out, "--json")
    theirs = pl.read_parquet(out)
    out2 = tmp_path / "caps2.parquet"
    cli("capacity", "--record", FAR, "--b", "0.15", "--h", "1", "--eps", "0.85", "--model", "auto",
        "--out", out2, "--json")
    theirs2 = pl.read_parquet(out2)
    assert table.height == 88
    assert table.schema == theirs.schema
    dtypes = dict(table.schema)
    assert dtypes["eta_c"] == pl.Float64 and dtypes["runs"] == pl.Int64
    assert dtypes["certified"] == pl.Boolean and dtypes["record_id"] == pl.String
    assert dtypes["pfa_over_pga"] == pl.Float64 and dtypes["model"] == pl.String
    skip = {"case_id"}
    mine = table.drop(skip)
    assert mine[0::2].equals(theirs.drop(skip))
    assert mine[1::2].equals(theirs2.drop(skip))
    # Arrays in, as a dict: the same capacities.
    recs = {p.stem: rocking.read_at2(p) for p in sorted(FAR.glob("*.AT2"))[:5]}
    t2 = rocking.capacities(recs, blocks[:1])
    assert t2["eta_c"].to_list() == theirs["eta_c"].to_list()[:5]
    assert t2["record_id"].to_list() == list(recs)


def test_a_pair_at_an_angle_is_the_command():
    b = FAR / "RSN1111_KOBE_NIS090.AT2"
    ours = rocking.capacity(KOBE, pair=b, angle=[0, 30, 210], b=0.2, h=0.9, eps="housner",
                            model="auto")
    theirs = cli_lines("capacity", "--record", KOBE, "--pair", b, "--angle", "0,30,210", "--b",
                       "0.2", "--h", "0.9", "--eps", "housner", "--model", "auto")
    assert len(ours) == len(theirs) == 3
    for a, c in zip(ours, theirs):
        same(a, c)
    assert ours[1]["eta_c"] == ours[2]["eta_c"]  # θ + 180° is θ's mirror image
    one = rocking.capacity(KOBE, pair=b, angle=30, b=0.2, h=0.9, eps="housner", model="auto")
    same(one, theirs[1])
    with pytest.raises(ValueError, match="the angle"):
        rocking.capacity(KOBE, pair=b, b=0.2, h=0.9, eps="housner")


def test_fragility_and_risk_are_the_commands():
    same(
        rocking.fragility(0.2, 0.9, eps=0.85, pga=[0.1, 0.3, 0.6]),
        cli_json("fragility", "--b", "0.2", "--h", "0.9", "--eps", "0.85", "--pga", "0.1,0.3,0.6"),
    )
    same(
        rocking.fragility(0.1, 1.0, eps=0.9, im="pgv", at=[20, 60], direct=True, records=FAR),
        cli_json("fragility", "--b", "0.1", "--h", "1", "--eps", "0.9", "--im", "pgv", "--at",
                 "20,60", "--direct", "--records", FAR),
    )
    # States on the slide, from the runs of the model that slides.
    same(
        rocking.fragility(0.3, 1.0, eps=0.75, mu=0.2, pga=[0.5, 1.0], direct=True, records=FAR,
                          states="walks=0.05m,off_plinth=0.3m"),
        cli_json("fragility", "--b", "0.3", "--h", "1", "--eps", "0.75", "--mu", "0.2", "--pga",
                 "0.5,1.0", "--direct", "--records", FAR, "--states",
                 "walks=0.05m,off_plinth=0.3m"),
    )
    # Over orientations, in a pair's IM: the records' pairs from the manifest.
    same(
        rocking.fragility(0.2, 0.9, im="rotd50_pga", at=[0.3], direct=True, records=FAR,
                          orientation="worst", angle_step=45),
        cli_json("fragility", "--b", "0.2", "--h", "0.9", "--im", "rotd50_pga", "--at", "0.3",
                 "--direct", "--records", FAR, "--orientation", "worst", "--angle-step", "45"),
    )
    same(
        rocking.risk(HAZARD, b=0.2, h=0.9, eps=0.85, mu=0.3),
        cli_json("risk", "--hazard", HAZARD, "--b", "0.2", "--h", "0.9", "--eps", "0.85", "--mu",
                 "0.3"),
    )
    inv = ROOT / "records" / "hazard" / "museum-inventory.csv"
    ours = rocking.risk(HAZARD, inventory=inv)
    theirs = worded(json.loads(cli("risk", "--hazard", HAZARD, "--inventory", inv, "--json",
                                   "--out", "/tmp/rocking-pytest-risk.parquet")))
    assert len(ours) == len(theirs) == 6
    for a, b in zip(ours, theirs):
        same(a, b)
    # The hazard as arrays: the same rate as from its file.
    text = HAZARD.read_text().splitlines()
    assert text[0].startswith("pga_g,annual_rate")
    pts = [tuple(map(float, line.split(","))) for line in text[1:] if line.strip()]
    levels, rates = zip(*pts)
    arr = rocking.risk((np.array(levels), np.array(rates)), hazard_im="pga", b=0.2, h=0.9, eps=0.85)
    one = rocking.risk(HAZARD, b=0.2, h=0.9, eps=0.85)
    assert arr["sites"][0]["annual_rate"] == one["sites"][0]["annual_rate"]


def test_a_tree_and_the_bootstrap_are_the_commands():
    """A logic tree (named, or a TOML file) and the rate's bootstrap band:
    Python's answers are the command line's."""
    same(
        rocking.risk(HAZARD, b=0.2, h=0.9, tree="restitution-tests"),
        cli_json("risk", "--hazard", HAZARD, "--b", "0.2", "--h", "0.9", "--tree",
                 "restitution-tests"),
    )
    same(
        rocking.fragility(0.2, 0.9, pga=[0.3, 0.5], tree="restitution-tests"),
        cli_json("fragility", "--b", "0.2", "--h", "0.9", "--pga", "0.3,0.5", "--tree",
                 "restitution-tests"),
    )
    same(
        rocking.risk(HAZARD, b=0.1, h=1.0, eps=0.8, direct=True, records=FAR, bootstrap=50,
                     seed=3),
        cli_json("risk", "--hazard", HAZARD, "--b", "0.1", "--h", "1", "--eps", "0.8",
                 "--direct", "--records", FAR, "--bootstrap", "50", "--seed", "3"),
    )
    with pytest.raises(ValueError, match="weights sum to"):
        bad = ROOT / "target" / "pytest-bad-tree.toml"
        bad.write_text("[[eps]]\nvalue = 0.8\nweight = 0.5\n")
        rocking.risk(HAZARD, b=0.2, h=0.9, tree=str(bad))


def test_risk_events_is_the_command(tmp_path):
    """Event-based fields (a hand-made OpenQuake export): Python's rates and
    counts are the command's."""
    g = tmp_path / "gmf"
    g.mkdir()
    meta = "#,,,\"generated_by='OpenQuake engine 3.26.2'\"\n"
    (g / "sitemesh_1.csv").write_text(meta + "custom_site_id,lon,lat\naaa,0.0,0.0\nbbb,0.1,0.0\n")
    (g / "events_1.csv").write_text(meta + "event_id,rup_id,rlz_id,year,ses_id\n0,0,0,1,1\n1,1,0,1,1\n")
    (g / "gmf-data_1.csv").write_text(
        meta + "event_id,gmv_PGA,custom_site_id\n0,0.45,aaa\n0,0.6,bbb\n1,0.3,aaa\n")
    inv = ROOT / "records" / "hazard" / "museum-inventory.csv"
    ours = rocking.risk_events(g, inventory=inv, eff_years=10)
    theirs = cli_json("risk", "--gmf", g, "--inventory", inv, "--eff-years", "10")
    assert ours["count_summary"] == theirs["counts"]
    rates = ours["rates"]
    assert rates.height == sum(len(b["sites"]) for b in theirs["blocks"])
    for b in theirs["blocks"]:
        for s in b["sites"]:
            row = rates.filter((pl.col("block") == b["block"]["name"]) & (pl.col("site") == s["site"]))
            assert row["annual_rate"][0] == s["annual_rate"]
    assert ours["counts"].filter(pl.col("k") == 0)["rate_at_least"].to_list()[0] == 2 / 10


def test_one_block_has_one_fragility_in_python_and_the_commands():
    """--direct's fit, median, β and records folder: Python's fragility and
    risk, and the commands' (which tests/risk.rs holds to export)."""
    f = rocking.fragility(0.2, 0.9, pga=[0.3], direct=True, records=FAR)
    r = rocking.risk(HAZARD, b=0.2, h=0.9, direct=True, records=FAR)
    c = cli_json("fragility", "--b", "0.2", "--h", "0.9", "--pga", "0.3", "--direct",
                 "--records", FAR)
    for got in (f, r["fragility"]):
        assert got["fit"] == c["fit"] == "fractile"
        assert (got["median"], got["beta"]) == (c["median"], c["beta"])
        assert got["records_folder"] == c["records_folder"] == str(FAR)
    s = rocking.risk(HAZARD, b=0.2, h=0.9, direct=True, records=FAR,
                     states="overturned=overturned")
    assert s["sites"][0]["states"][0]["annual_rate"] == r["sites"][0]["annual_rate"]
    e = rocking.fragility(0.2, 0.9, pga=[0.3], direct=True, records=FAR, method="empirical")
    ce = cli_json("fragility", "--b", "0.2", "--h", "0.9", "--pga", "0.3", "--direct",
                  "--records", FAR, "--method", "empirical")
    assert e["fit"] == ce["fit"] == "empirical"
    assert e["points"][0]["probability"] == ce["points"][0]["probability"]
    # The records' curve is linear between their capacities: within one
    # rank, 1/(n - 1), of the share of records overturned there.
    assert abs(e["points"][0]["probability"] - e["points"][0]["empirical"]) <= 1 / 43


def test_where_a_lognormal_does_not_fit_both_take_the_records_curve():
    """The statue with eps = 0.85 fails the lognormal check: Python, like the
    command line, takes the records' curve, or the lognormal when asked."""
    args = ("--b", "0.2", "--h", "0.9", "--eps", "0.85", "--pga", "0.3,0.8", "--direct",
            "--records", FAR)
    f = rocking.fragility(0.2, 0.9, eps=0.85, pga=[0.3, 0.8], direct=True, records=FAR)
    c = cli_json("fragility", *args)
    assert f["fit"] == c["fit"] == "empirical"
    assert f["lognormal_p"] == c["lognormal_p"] < 0.05
    assert [p["probability"] for p in f["points"]] == [p["probability"] for p in c["points"]]
    k = rocking.fragility(0.2, 0.9, eps=0.85, pga=[0.3, 0.8], direct=True, records=FAR,
                          if_not_lognormal="lognormal")
    ck = cli_json("fragility", *args, "--if-not-lognormal", "lognormal")
    assert k["fit"] == ck["fit"] == "fractile"
    assert k["points"] == ck["points"]


def test_a_floor_demand_is_the_commands():
    """PFV on a floor, from the block's runs: Python's is the command's,
    the floor given as a list of modes or as the command's text (which was
    read as a list of its characters and refused for its first, `0`)."""
    cli = cli_json("fragility", "--b", "0.2", "--h", "0.9", "--im", "pfv", "--at", "40,80",
                   "--direct", "--records", FAR, "--floor", "0.5,0.05,1.3")
    for floor in ([(0.5, 0.05, 1.3)], "0.5,0.05,1.3"):
        same(
            rocking.fragility(0.2, 0.9, im="pfv", at=[40, 80], direct=True, records=FAR,
                              floor=floor),
            cli,
        )


def test_bad_input_raises_value_errors_with_the_librarys_message(tmp_path):
    bad = tmp_path / "bad.AT2"
    bad.write_text("A\nB\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 3, DT= 0.01 SEC\n0.1 x 0.3\n")
    with pytest.raises(ValueError, match=r"bad\.AT2:5:"):
        rocking.read_at2(bad)
    acc = np.zeros(100)
    acc[10] = np.nan
    with pytest.raises(ValueError, match="non-finite sample nan at index 10"):
        rocking.capacity(acc, 0.01, p=2, eps=0.7)
    with pytest.raises(ValueError, match=re.escape("a time step of -1e-2 s")):
        rocking.capacity(np.ones(10), -0.01, p=2, eps=0.7)
    with pytest.raises(ValueError, match="1-D array"):
        rocking.capacity(np.ones((10, 2)), 0.01, p=2, eps=0.7)
    with pytest.raises(ValueError, match="unknown model `quadratic`; valid: linearized, nonlinear, auto"):
        rocking.capacity(KOBE, p=2, eps=0.7, model="quadratic")
    with pytest.raises(ValueError, match=r"ε = 1.5 must be in \(0, 1\]"):
        rocking.capacity(KOBE, p=2, eps=1.5)
    with pytest.raises(ValueError, match="mu is compared with the block's b/h"):
        rocking.capacity(KOBE, p=2, eps=0.7, mu=0.3)
    with pytest.raises(ValueError, match="floor: mode 1: damping ratio"):
        rocking.capacity(KOBE, p=2, eps=0.7, floor=[(0.5, 1.5, 1.0)])
    with pytest.raises(ValueError, match=r"add direct=True"):
        rocking.fragility(0.2, 0.9, pga=[0.3], floor=[(0.5, 0.05, 1.3)])
    with pytest.raises(ValueError, match="blocks\\[0\\]: unknown field `colour`"):
        rocking.capacities(FAR, [dict(p=2, eps=0.7, colour="red")])
    with pytest.raises(ValueError, match="unknown field `colour`"):
        rocking.fragility(0.2, 0.9, pga=[0.3], colour="red")
    with pytest.raises(ValueError, match="mu_k is the kinetic friction beside mu: give both"):
        rocking.simulate(KOBE, b=0.2, h=1.0, eps=0.9, pga=0.3, mu_k=0.2)
    with pytest.raises(ValueError, match=re.escape("give a block's b and h (half sizes, m), "
                                                   "or inventory: h is missing")):
        rocking.risk(HAZARD, b=0.2)
    with pytest.raises(ValueError, match="hazard: point 2: levels must increase"):
        rocking.risk(([0.1, 0.05], [1e-2, 1e-3]), hazard_im="pga", b=0.2, h=0.9)
    # Arrays carry no unit: a PGV curve (cm/s) taken for PGA (g) would be
    # 600 times the rate.
    with pytest.raises(ValueError, match="hazard_im: levels given as arrays carry no unit"):
        rocking.risk(([20.0, 40.0], [1e-2, 1e-3]), b=0.2, h=0.9)
    with pytest.raises(ValueError, match='eps="housner" needs the block\'s dimensions'):
        rocking.Block(p=2, eps="housner")
    with pytest.warns(UserWarning, match="slides before it rocks"):
        r = rocking.capacity(KOBE, b=0.4, h=1.0, eps=0.8, mu=0.2)
    assert r["slides_first"] is True


def test_a_block_the_size_of_a_building_is_warned_of_once():
    # Sizes in cm ran as a 180 m block without a word in simulate and
    # capacity: Block warns, as the commands do, once for its two ε.
    big = rocking.Block(b=20, h=90, eps=[0.8, 0.9])
    sized = [w for w in big.warnings if "building's size" in w]
    assert len(sized) == 1 and "a block 180 m tall" in sized[0]
    # Beside it, once too, the linearised model (capacity's and simulate's
    # default) beyond its accepted error at this α, in Python's words.
    linear = [w for w in big.warnings if "the linearised model errs by about" in w]
    assert len(linear) == 1 and 'auto_tol' in linear[0] and 'model="auto"' in linear[0], linear
    assert len(big.warnings) == 2
    assert rocking.Block(b=0.2, h=0.9, eps=0.9, model="auto").warnings == []
    assert rocking.Block(b=0.1, h=0.9, eps=0.9).warnings == []


def test_the_gil_is_released_while_a_batch_computes():
    count = [0]
    running = threading.Event()
    stop = threading.Event()

    def counter():
        running.set()
        while not stop.is_set():
            count[0] += 1

    t = threading.Thread(target=counter)
    t.start()
    running.wait()
    before = count[0]
    started = time.perf_counter()
    rocking.capacities(FAR, [dict(b=0.2, h=0.9, eps=0.85, model="nonlinear")])
    seconds = time.perf_counter() - started
    during = count[0] - before
    stop.set()
    t.join()
    # Holding the GIL the whole call would let the counter take only the
    # interpreter's switch intervals (5 ms) at the call's edges.
    assert seconds > 0.05, seconds
    assert during > 10_000, (during, seconds)


def test_ctrl_c_stops_a_long_call_and_the_next_call_runs():
    # 44 records × 1,000 blocks: about 45 s on two cores uninterrupted,
    # where the call used to run to its end before Python saw the signal.
    blocks = [dict(p=float(p), eps=0.7) for p in np.geomspace(0.5, 10.0, 1000)]
    # Python's own Ctrl-C handler, as a terminal or a notebook has it (a
    # process started in the background inherits SIGINT ignored).
    signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    started = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            rocking.capacities(FAR, blocks)
    finally:
        timer.cancel()
    seconds = time.perf_counter() - started
    # It stops at the next run of every worker: milliseconds after the
    # signal; the bound leaves a slow machine ten seconds.
    assert seconds < 10.0, seconds
    # The stop is withdrawn: the next call runs, and gives the command's answer.
    one = rocking.capacity(KOBE, p=2, eps=0.7)
    same(one, cli_json("capacity", "--record", KOBE, "--p", 2, "--eps", 0.7))


def test_ctrl_c_in_the_main_thread_leaves_another_threads_call_its_answer():
    # Python delivers Ctrl-C to its main thread; the library's stop is
    # process-wide, so a call in another thread was stopped with it, and
    # failed with an interruption nobody asked for. It now runs again, to
    # the answer of a call never stopped.
    blocks = [dict(p=float(p), eps=0.7) for p in np.geomspace(0.5, 10.0, 1000)]
    small = [dict(p=float(p), eps=0.7) for p in (1.0, 2.0, 4.0)]
    expected = rocking.capacities(FAR, small)
    got = {}

    def worker():
        try:
            got["table"] = rocking.capacities(FAR, small * 40)
        except BaseException as e:  # noqa: BLE001 - the finding is what it raised
            got["error"] = e

    signal.signal(signal.SIGINT, signal.default_int_handler)
    t = threading.Thread(target=worker)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    t.start()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            rocking.capacities(FAR, blocks)
    finally:
        timer.cancel()
        t.join()
    assert "error" not in got, got
    table = got["table"]
    assert table.height == 40 * expected.height
    # Every case's answer (its number in the batch aside) is the lone call's.
    keep = [c for c in expected.columns if c != "case_id"]
    assert table.select(keep).unique().sort(keep).equals(expected.select(keep).sort(keep))


def tiny_pipeline(tmp_path):
    """Three records' study of 2 × 2 blocks, written into tmp_path."""
    rec = ROOT / "records" / "fema-p695"
    pipeline = tmp_path / "tiny.toml"
    pipeline.write_text(
        'name = "tiny"\n[records]\n'
        f'at2 = ["{rec}"]\nmanifest = "{rec / "manifest.csv"}"\n'
        'ids = ["RSN1111_KOBE_NIS000", "RSN1116_KOBE_SHI000", "RSN1148_KOCAELI_ARC000"]\n'
        "[blocks]\np = [1.0, 3.0]\neps = [0.7, 0.9]\n"
    )
    return pipeline


def test_run_and_load_give_the_commands_tables(tmp_path):
    pipeline = tiny_pipeline(tmp_path)
    ran = rocking.run(pipeline, tmp_path / "py")
    assert [r["stage"] for r in ran if r["ran"]][:2] == ["ingest", "sweep"]
    again = rocking.run(pipeline, tmp_path / "py")
    assert not any(r["ran"] for r in again)
    cli("run", pipeline, "--outputs", tmp_path / "cli")
    ours = rocking.load(pipeline, tmp_path / "py")
    theirs = rocking.load(pipeline, tmp_path / "cli")
    assert {"capacities", "ida_points", "capacity_fractiles", "records"} <= set(ours)
    assert set(ours) == set(theirs)
    for name in ours:
        assert ours[name].equals(theirs[name]), name
    assert ours["capacities"].height == 12
    # One build, named alike by the package, the command and the study's notes.
    assert cli("--version").strip() == f"rocking {rocking.__build__}"
    assert rocking.__build__.startswith(rocking.__version__ + " (sources ")
    note = json.loads((tmp_path / "py" / "tiny" / ".fingerprints" / "sweep.json").read_text())
    assert f"rocking {rocking.__build__}" in json.dumps(note)
    with pytest.raises(ValueError, match="no study here yet"):
        rocking.load(pipeline, tmp_path / "nowhere")


def test_a_run_stopped_by_ctrl_c_resumes_to_the_commands_tables(tmp_path):
    # The quick study takes about 3 s; stopped at 0.3 s, in its sweep.
    quick = ROOT / "pipelines" / "quick.toml"
    signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            rocking.run(quick, tmp_path / "py", force=True)
    finally:
        timer.cancel()
    # Nothing half-written: the next run finishes what was stopped, and every
    # table is the command's, from a run never stopped.
    again = rocking.run(quick, tmp_path / "py")
    assert any(r["ran"] for r in again)
    cli("run", quick, "--outputs", tmp_path / "cli")
    ours = rocking.load(quick, tmp_path / "py")
    theirs = rocking.load(quick, tmp_path / "cli")
    assert set(ours) == set(theirs) and "capacities" in ours
    for name in ours:
        assert ours[name].equals(theirs[name]), name


def test_every_im_passes_pythons_doors_by_its_own_answers():
    listed = rocking.ims()
    assert [m["name"] for m in listed[:3]] == ["pga", "pgv", "pgd"]
    assert {m["key"] for m in listed} >= {"pga_g", "pgv_cm_s", "d5_95_s", "sa(1.0)_g"}
    # The floor demands, the floor's SA at 1 s standing for any period.
    assert [m["name"] for m in listed if m["floor"]] == ["pfa", "pfv", "fsa(1.0)"]
    # A pair's measures, SA at 1 s standing for any period.
    assert [m["name"] for m in listed if m["pair"]] == [
        "rotd50_pga", "rotd50_pgv", "rotd50_sa(1.0)", "rotd100_pga", "rotd100_pgv",
        "rotd100_sa(1.0)"]
    for m in listed:
        try:
            rocking.fragility(0.2, 0.9, im=m["name"], at=[1.0])
            refused = False
        except ValueError as e:
            refused = "a capacity cannot be stated in" in str(e)
            # A floor demand is the block's own runs' (direct=True).
            assert ("a demand of the motion the block stands on" in str(e)) == m["floor"], e
            # A pair's measure is had from the records' pairs (direct=True).
            assert ("a measure of a record pair" in str(e)) == m["pair"], e
        assert refused == (not m["scales"]), m
        try:
            rocking.risk(([0.1, 0.2], [1e-2, 1e-3]), hazard_im=m["name"], b=0.2, h=0.9, direct=False)
            accepted = True
        except ValueError as e:
            accepted = "hazard curves are in" not in str(e)
        assert accepted == m["hazard"], m


def test_export_is_the_commands(tmp_path):
    """The same block exported to pelicun from Python and from the command
    line: the same blocks, the same CSV to the byte (the records' curves of
    the statue with eps = 0.85, whose capacities are not lognormal)."""
    py = rocking.export(tmp_path / "py", format="pelicun", b=0.2, h=0.9, eps=0.85,
                        direct=True, records=FAR)
    c = worded(json.loads(cli("export", "--format", "pelicun", "--b", "0.2", "--h", "0.9",
                              "--eps", "0.85", "--direct", "--records", FAR,
                              "--out", tmp_path / "cli", "--json")))
    assert py["blocks"] == c
    assert py["blocks"][0]["written_as"] == "curve"
    assert [os.path.basename(f) for f in py["files"]] == ["fragility.csv", "fragility.json"]
    assert (tmp_path / "py" / "fragility.csv").read_bytes() == \
        (tmp_path / "cli" / "fragility.csv").read_bytes()
    with pytest.raises(ValueError, match="format"):
        rocking.export(tmp_path / "x", b=0.2, h=0.9)


def test_a_building_is_the_commands():
    """A building's floor from Python's lists is the command line's."""
    modes = [[0.5, 0.05, 1.25, 0.45, 0.8, 1.0], [0.18, 0.05, -0.35, 1.0, -0.5, -1.0]]
    f = rocking.fragility(0.2, 0.9, direct=True, records=FAR, im="pfv", at=[40, 80],
                          building=modes, level=2)
    c = cli_json("fragility", "--b", "0.2", "--h", "0.9", "--direct", "--records", FAR,
                 "--im", "pfv", "--at", "40,80", "--building", "0.5,0.05,1.25,0.45,0.8,1",
                 "--building", "0.18,0.05,-0.35,1,-0.5,-1", "--level", "2")
    assert (f["median"], f["beta"], f["floor"]) == (c["median"], c["beta"], c["floor"])
    with pytest.raises(ValueError, match="level 4: the building has floors 1–3"):
        rocking.fragility(0.2, 0.9, direct=True, records=FAR, im="pfv", at=[40],
                          building=modes, level=4)


def test_inputs_that_ran_as_something_else_are_refused_by_keyword():
    # A record of zeros ran (η = 0.729, θmax = 0) though it cannot be scaled
    # to any PGA; a step of 1e6 s and a single sample ran as records.
    for acc, dt, says in [
        (np.zeros(100), 0.01, "every sample is 0"),
        (np.array([0.1, -0.2, 0.05]), 1e6, "a time step of 1e6 s"),
        (np.array([0.1]), 0.01, "a motion needs two at least"),
        (np.array([0.1, 25.0]), 0.01, "past 10 g"),
    ]:
        with pytest.raises(ValueError, match=re.escape(says)):
            rocking.simulate(acc, dt, pga=0.3, p=2.0, eps=0.7)
        with pytest.raises(ValueError, match=re.escape(says)):
            rocking.capacity(acc, dt, p=2.0, eps=0.7)
    # An empty floor ran the block on the ground; no angle and no record
    # gave empty answers.
    with pytest.raises(ValueError, match=r"floor: no mode given"):
        rocking.fragility(0.2, 0.9, pga=[0.3], direct=True, floor=[])
    with pytest.raises(ValueError, match=r"angle: none given"):
        rocking.capacity(KOBE, pair=FAR / "RSN1111_KOBE_NIS090.AT2", angle=[], p=2.0, eps=0.7)
    with pytest.raises(ValueError, match=r"records: none given"):
        rocking.capacities([], [rocking.Block(p=2.0, eps=0.7)])
    # Refusals worded in the library's internals ("untagged enum Given",
    # an OverflowError of an unsigned integer) name the keyword instead.
    with pytest.raises(ValueError, match=r"^floor: a mode is three numbers"):
        rocking.fragility(0.2, 0.9, pga=[0.3], direct=True, floor=[(0.5, 0.05)])
    hazard = ([0.1, 0.5, 1.0], [1e-2, 1e-3, 1e-4])
    with pytest.raises(ValueError, match=r'^hazard_im = "foo"'):
        rocking.risk(hazard, hazard_im="foo", b=0.2, h=0.9)
    with pytest.raises(ValueError, match=r"^site: a whole number \(it was negative\)"):
        rocking.risk(hazard, hazard_im="pga", b=0.2, h=0.9, site=-1)
    with pytest.raises(ValueError, match=r"^site: a whole number \(it was a str\)"):
        rocking.risk(hazard, hazard_im="pga", b=0.2, h=0.9, site="1")
    with pytest.raises(ValueError, match=r"^site: a whole number \(it was a float\)"):
        rocking.risk(hazard, hazard_im="pga", b=0.2, h=0.9, site=1.5)
    with pytest.raises(ValueError, match=r"^levels: a whole number \(it was negative\)"):
        rocking.capacity(KOBE, p=2.0, eps=0.7, levels=-1)


def test_paths_flags_and_hazards_of_the_wrong_kind_are_refused_by_keyword(tmp_path):
    # A path of another type, a flag that is not a bool and a hazard of
    # three arrays raised TypeErrors of Python's own, naming no keyword.
    with pytest.raises(ValueError, match=r"^out: give a path"):
        rocking.export(None, format="pelicun", b=0.2, h=0.9)
    with pytest.raises(ValueError, match=r"^pipeline: give a path"):
        rocking.run(None, tmp_path)
    with pytest.raises(ValueError, match=r"^force: give True or False"):
        rocking.run(ROOT / "pipelines" / "quick.toml", tmp_path, force="no")
    levels, rates = [0.1, 0.5, 1.0], [1e-2, 1e-3, 1e-4]
    with pytest.raises(ValueError, match=r"^hazard: give a file, or \(levels, annual_rates\)"):
        rocking.risk((levels, rates, rates), b=0.2, h=0.9)
    with pytest.raises(ValueError, match=r"^hazard: levels and annual rates must be numbers"):
        rocking.risk((["a", "b"], [0.1, 0.2]), b=0.2, h=0.9)
    # A list could be two arrays or (level, rate) pairs: refused, not guessed.
    with pytest.raises(ValueError, match=r"^hazard: give a file, or a tuple"):
        rocking.risk([levels, rates], b=0.2, h=0.9)
    # The command's --from is Python's source (from is a word Python reserves).
    with pytest.raises(ValueError) as e:
        rocking.fragility(0.2, 0.9, pga=[0.3], outputs=tmp_path)
    assert "source=" in str(e.value) and "from=" not in str(e.value), str(e.value)


def test_a_block_pickles_compares_and_shows_its_blocks():
    import copy
    import pickle

    blk = rocking.Block(b=0.2, h=0.9, eps=0.85)
    again = pickle.loads(pickle.dumps(blk))
    assert again == blk and copy.deepcopy(blk) == blk
    assert repr(blk) == "Block(b=0.2, h=0.9, eps=0.85)"
    # One number or a list of one: the same block.
    assert rocking.Block(b=[0.2], h=0.9, eps=0.85) == blk
    assert rocking.Block(b=0.2, h=0.9, eps=0.8) != blk
    assert len({blk, again, rocking.Block(b=0.2, h=0.9, eps=0.8)}) == 2
    # The caller's list changed after: the block, its repr and pickle not.
    ps = [1.0]
    grid = rocking.Block(p=ps, eps=0.7)
    ps.append(2.0)
    assert repr(grid) == "Block(p=[1.0], eps=0.7)" and len(pickle.loads(pickle.dumps(grid))) == 1
    # α = atan(b/h) and p = sqrt(3g/(4R)), R = sqrt(b² + h²), by hand.
    (one,) = blk.blocks
    r = (0.2**2 + 0.9**2) ** 0.5
    assert abs(one["alpha_rad"] - np.arctan(0.2 / 0.9)) < 1e-15
    assert abs(one["p"] / (3 * 9.80665 / (4 * r)) ** 0.5 - 1) < 1e-15  # standard gravity
    assert one["eps"] == 0.85 and one["mu"] is None
    # A pickled block runs as the original.
    assert rocking.capacity(KOBE, block=again) == rocking.capacity(KOBE, block=blk)
    assert len(rocking.Block(p=[1, 2, 4], eps=[0.7, 0.9]).blocks) == 6


def test_python_arguments_are_read_or_refused_by_name():
    acc, dt = rocking.read_at2(KOBE)
    # A dict as the block, an int record_id, a 1-element dt, angles as a
    # range or an array: read as the command reads them.
    by_dict = rocking.capacity(KOBE, block=dict(p=2.0, eps=0.7))
    assert by_dict["eta_c"] == rocking.capacity(KOBE, p=2.0, eps=0.7)["eta_c"]
    named = rocking.capacity(acc, np.array([dt]), p=2.0, eps=0.7, record_id=5)
    assert named["record_id"] == "5" and named["eta_c"] == by_dict["eta_c"]
    pair = FAR / "RSN1111_KOBE_NIS090.AT2"
    listed = rocking.capacity(KOBE, pair=pair, angle=[0, 60, 120], p=2.0, eps=0.7)
    assert rocking.capacity(KOBE, pair=pair, angle=range(0, 180, 60), p=2.0, eps=0.7) == listed
    assert rocking.capacity(KOBE, pair=pair, angle=np.array([0, 60, 120]), p=2.0, eps=0.7) == listed
    # One block, not in a list.
    one = rocking.capacities([KOBE], dict(p=2.0, eps=0.7))
    assert one["eta_c"][0] == by_dict["eta_c"]
    # Arguments that were ignored are refused.
    with pytest.raises(ValueError, match="dt comes from the AT2 file"):
        rocking.capacity(KOBE, 0.02, p=2.0, eps=0.7)
    with pytest.raises(ValueError, match="record_id names an array record"):
        rocking.capacity(KOBE, p=2.0, eps=0.7, record_id="x")
    with pytest.raises(ValueError, match="record_id names an array record"):
        rocking.simulate(KOBE, p=2.0, eps=0.7, eta=0.3, record_id="x")
    with pytest.raises(ValueError, match="record_id: give a name"):
        rocking.capacity(acc, dt, p=2.0, eps=0.7, record_id="")
    # Wrong types, named.
    with pytest.raises(ValueError, match="^eta: give one number"):
        rocking.simulate(KOBE, p=2.0, eps=0.7, eta=[0.3, 0.4])
    with pytest.raises(ValueError, match="^dt: give one number"):
        rocking.capacity(acc, np.array([0.01, 0.02]), p=2.0, eps=0.7)
    with pytest.raises(ValueError, match="^block: give a Block or a dict"):
        rocking.capacity(KOBE, block=[2.0, 0.7])
    with pytest.raises(ValueError, match=r'^eps: give a number in \(0, 1\] or "housner"'):
        rocking.risk(HAZARD, b=0.2, h=0.9, eps=[0.8, 0.9])
    # None is a keyword not given; states as a list.
    assert rocking.fragility(0.2, 0.9, pga=[0.3], eps=None) == rocking.fragility(0.2, 0.9, pga=[0.3])
    listed = rocking.fragility(0.2, 0.9, pga=[0.3], direct=True,
                               states=["rocking=0.1", "overturned=overturned"])
    text = rocking.fragility(0.2, 0.9, pga=[0.3], direct=True, states="rocking=0.1,overturned=overturned")
    assert listed == text


def test_record_ims_are_the_commands():
    pair = FAR / "RSN1111_KOBE_NIS090.AT2"
    ours = rocking.record_ims(KOBE, pair=pair, periods=[0.37])
    theirs = cli_json("ims", "--record", KOBE, "--pair", pair, "--period", 0.37)
    assert ours == theirs
    # From arrays, the same numbers; PGA is the largest |sample| (a record's
    # peak, read off the samples independently).
    acc, dt = rocking.read_at2(KOBE)
    alone = rocking.record_ims(acc, dt)
    assert alone == cli_json("ims", "--record", KOBE)
    assert alone["pga_g"] == float(np.max(np.abs(acc)))
    with pytest.raises(ValueError, match="periods: -1 is not a positive number"):
        rocking.record_ims(KOBE, periods=[-1])
    with pytest.raises(ValueError, match="dt comes from the AT2 file"):
        rocking.record_ims(KOBE, 0.01)
    # One period as a NumPy integer; a text refused whole; a pair's array
    # without its step named as pair_dt.
    assert rocking.record_ims(KOBE, periods=np.int64(1))["sa_g"]["1.0"] == alone["sa_g"]["1.0"]
    with pytest.raises(ValueError, match="^periods: give numbers"):
        rocking.record_ims(KOBE, periods="1.0")
    b, _ = rocking.read_at2(pair)
    with pytest.raises(ValueError, match="^the pair is an array: give its time step pair_dt"):
        rocking.record_ims(KOBE, pair=b)


def test_a_history_is_the_commands_table(tmp_path):
    import polars as pl

    path = tmp_path / "h.parquet"
    cli("simulate", "--record", KOBE, "--p", 2, "--eps", 0.7, "--eta", 0.4,
        "--history", path, "--history-every", 5)
    ours = rocking.simulate(KOBE, p=2.0, eps=0.7, eta=0.4, history=5)
    theirs = pl.read_parquet(path)
    assert ours["history"].equals(theirs)
    h = ours["history"]
    # Every impact of the answer is an event row of the history.
    assert h.filter(pl.col("event") == "impact").height == ours["impacts"]
    # Time runs forward; the samples kept are every 5th.
    assert (h["t_s"].diff().drop_nulls() >= 0).all()
    assert "history" not in rocking.simulate(KOBE, p=2.0, eps=0.7, eta=0.4)
    with pytest.raises(ValueError, match="^history: give True, False or a whole number"):
        rocking.simulate(KOBE, p=2.0, eps=0.7, eta=0.4, history=0)


def test_run_takes_the_commands_stage_options(tmp_path):
    pipeline = tiny_pipeline(tmp_path)
    out = tmp_path / "py"
    # Through the sweep only: the later stages wait.
    ran = rocking.run(pipeline, out, to="sweep", threads=1)
    assert [r["stage"] for r in ran if r["ran"]] == ["ingest", "sweep"]
    assert [r["stage"] for r in ran] == ["ingest", "sweep"]
    # From the reduce stage, forced, and what it needs only.
    again = rocking.run(pipeline, out, from_="reduce")
    assert "reduce" in [r["stage"] for r in again if r["ran"]]
    assert not any(r["ran"] for r in again if r["stage"] in ("ingest", "sweep"))
    # The command's tables, to the bit.
    cli("run", pipeline, "--outputs", tmp_path / "cli")
    ours, theirs = rocking.load(pipeline, out), rocking.load(pipeline, tmp_path / "cli")
    for name in ("capacities", "capacity_fractiles"):
        assert ours[name].equals(theirs[name]), name
    with pytest.raises(ValueError, match="^to: unknown stage `swep`; valid: ingest"):
        rocking.run(pipeline, out, to="swep")
    with pytest.raises(ValueError, match="0: give one worker thread or more"):
        rocking.run(pipeline, out, force=True, threads=0)
