"""Damaged or forged plane stores (issue 23, item 13): ``plot`` and a resumed ``plane``
refuse them with one line naming the store, exit 2, and leave them as they were."""
import json
import os
import shutil

import pytest

from tests.fuzz._cli import assert_bad_input, cli, snapshot

FLAGS = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
PLANE = ["plane", *FLAGS, "--x", "omega:0.7:0.8:4", "--y", "b:1.3:1.7:4", "--impacts", "20",
         "--transient", "20", "--workers", "0", "--out"]


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    path = tmp_path_factory.mktemp("good") / "p.zarr"
    rc, _, err = cli(*PLANE, path)
    assert rc == 0, err
    return path


def _edit_json(store, key, fn):
    """Apply ``fn`` to the metadata document ``key`` (e.g. "done/.zarray") in its file and
    in the consolidated .zmetadata, as a forger would."""
    p = os.path.join(store, key)
    doc = json.load(open(p))
    fn(doc)
    json.dump(doc, open(p, "w"))
    zp = os.path.join(store, ".zmetadata")
    meta = json.load(open(zp))
    fn(meta["metadata"][key])
    json.dump(meta, open(zp, "w"))


def _edit_spec(fn):
    def edit(store):
        def attrs(a):
            spec = json.loads(a["spec"])
            fn(spec)
            a["spec"] = json.dumps(spec, sort_keys=True)
        _edit_json(store, ".zattrs", attrs)
    return edit


def _garbage(rel):
    def edit(store):
        with open(os.path.join(store, rel), "wb") as fh:
            fh.write(b"not a blosc chunk")
    return edit


def _drop(var):
    def edit(store):
        shutil.rmtree(os.path.join(store, var))
        zp = os.path.join(store, ".zmetadata")
        meta = json.load(open(zp))
        for k in [k for k in meta["metadata"] if k.startswith(var + "/")]:
            del meta["metadata"][k]
        json.dump(meta, open(zp, "w"))
    return edit


DAMAGE = {
    "done-shape": lambda s: _edit_json(s, "done/.zarray", lambda d: d.update(shape=[2])),
    "attractor-shape": lambda s: _edit_json(s, "attractor/.zarray",
                                            lambda d: d.update(shape=[4, 3])),
    "label-width": lambda s: _edit_json(s, "stop/.zarray", lambda d: d.update(dtype="<U4")),
    "period-dtype": lambda s: _edit_json(s, "period/.zarray", lambda d: d.update(dtype="<f8")),
    "done-chunk": _garbage("done/0"),
    "attractor-chunk": _garbage("attractor/0.0"),
    "no-attractor": _drop("attractor"),
    "no-done": _drop("done"),
    "zmetadata": lambda s: open(os.path.join(s, ".zmetadata"), "w").write("{"),
    "format": lambda s: _edit_json(s, ".zattrs", lambda a: a.update(symvi_plane_format=99)),
    "spec-not-json": lambda s: _edit_json(s, ".zattrs", lambda a: a.update(spec="{")),
    "spec-a-list": lambda s: _edit_json(s, ".zattrs", lambda a: a.update(spec="[1]")),
    "spec-no-key": _edit_spec(lambda d: d.pop("impacts")),
    "spec-model": _edit_spec(lambda d: d.update(model="[[[")),
    "spec-axis": _edit_spec(lambda d: d.update(x="omega:0.7:0.8:5")),
    "spec-type": _edit_spec(lambda d: d.update(impacts=[1])),
}


@pytest.mark.parametrize("damage", sorted(DAMAGE))
def test_damaged_store_refused_by_plot_and_resume(good, tmp_path, damage):
    store = tmp_path / "d.zarr"
    shutil.copytree(good, store)
    DAMAGE[damage](str(store))
    before = snapshot(tmp_path)
    assert_bad_input(cli("plot", store, "--plot", tmp_path / "d.png", "--no-curves"),
                     "store", "d.zarr")
    assert_bad_input(cli(*PLANE, store), "--out", "d.zarr")
    assert snapshot(tmp_path) == before


def test_damaged_data_chunk_refused_by_plot(good, tmp_path):
    store = tmp_path / "d.zarr"
    shutil.copytree(good, store)
    _garbage("lyapunov/1.0")(str(store))
    before = snapshot(tmp_path)
    line = assert_bad_input(cli("plot", store, "--plot", tmp_path / "d.png", "--no-curves"),
                            "store", "damaged")
    assert "d.zarr" in line and snapshot(tmp_path) == before


@pytest.mark.parametrize("what", ["file", "folder", "missing", "fifo"])
def test_plot_of_a_non_store(tmp_path, what):
    p = tmp_path / "s.zarr"
    if what == "file":
        p.write_text("x")
    elif what == "folder":
        p.mkdir()
    elif what == "fifo":
        os.mkfifo(p)
    before = snapshot(tmp_path)
    assert_bad_input(cli("plot", p, "--plot", tmp_path / "x.png"), "store")
    assert snapshot(tmp_path) == before
