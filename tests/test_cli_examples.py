"""Every `meshsmith` command's documented examples (the "examples" of its --help) run on small
generated inputs and write valid outputs; the bad-usage cases of issue 14 print one line, no
traceback, with the right exit status; Ctrl-C stops a long ABF within a second."""
import json
import os
import pty
import select
import shlex
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from meshsmith import cli, datasets, decimation, io

MESH_SUFFIXES = (".obj", ".off", ".ply", ".stl")


def run(*args, cwd=None, env=None):
    """The real entry point, as a user runs it."""
    return subprocess.run([sys.executable, "-m", "meshsmith", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, env=env)


def documented_examples():
    """(command, example) for every example of every command, read from the parser itself."""
    parser = cli.build_parser()
    commands = next(action for action in parser._actions if action.dest == "command")
    return [(name, example) for name, sub in commands.choices.items() for example in sub.examples]


def test_every_command_documents_examples():
    parser = cli.build_parser()
    commands = next(action for action in parser._actions if action.dest == "command")
    for name, sub in commands.choices.items():
        assert len(sub.examples) >= 1, name
        assert "examples:" in sub.format_help() and sub.examples[0] in sub.format_help()


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """The files the examples name, generated from meshsmith.datasets."""
    folder = tmp_path_factory.mktemp("examples")
    V, F = datasets.icosphere(2)
    io.write_mesh(folder / "mesh.off", V, F)
    Vd, Fd = datasets.disk(8, 32)
    Vd = np.column_stack([Vd[:, :2], 0.2 * (Vd[:, :2] ** 2).sum(axis=1)])   # a cap: not flat
    io.write_mesh(folder / "disk.obj", Vd, Fd)
    P, _ = datasets.sample_points(V, F, 1500, seed=3)
    io.write_points(folder / "points.xyz", P)
    pm = decimation.progressive_mesh(V, F, target_faces=100)
    pm.save(folder / "mesh.pm")
    rng = np.random.default_rng(5)
    np.savetxt(folder / "points.txt", rng.random((40, 2)))
    angles = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    np.savetxt(folder / "circle.txt", np.column_stack([np.cos(angles), np.sin(angles)]))
    np.savetxt(folder / "weighted.txt", np.column_stack([rng.random((30, 2)), 0.01 * rng.random(30)]))
    c, s = np.cos(0.5), np.sin(0.5)
    np.savetxt(folder / "rotate.txt", [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0.2], [0, 0, 0, 1]])
    np.savetxt(folder / "lift.txt", [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.3]])   # 3x4: the last row implied
    (folder / "domain.poly").write_text(
        "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
    return folder


def outputs_of(words):
    """The files an example writes: the values of -o/--output, --picture, --progressive, --out,
    and convert's second operand."""
    found = []
    for flag in ("-o", "--output", "--picture", "--progressive", "--out", "--apply"):
        if flag in words:
            found.append(words[words.index(flag) + 1])
    if words[1] == "convert":
        found.append([w for w in words[2:] if not w.startswith("-")][1])
    return found


def check_valid(path, command):
    """The output exists and is what its name says."""
    assert path.exists(), path
    suffix = path.suffix.lower()
    if command == "normals":
        P, N = io.read_points(path)
        assert len(P) > 0 and np.allclose(np.linalg.norm(N, axis=1), 1, atol=1e-6)
    elif path.is_dir():
        assert (path / "index.html").stat().st_size > 1000
    elif suffix == ".png":
        from PIL import Image
        with Image.open(path) as image:
            image.load()
            assert image.size[0] >= 16 and image.size[1] >= 16
    elif suffix in MESH_SUFFIXES:
        V, F = io.read_mesh(path)
        assert len(V) > 0 and len(F) > 0 and np.isfinite(V).all()
    elif suffix == ".npy":
        assert np.isfinite(np.load(path)).all()
    elif suffix == ".txt" and command == "register":
        T = np.loadtxt(path)
        assert T.shape == (4, 4) and np.allclose(T[3], [0, 0, 0, 1]) and np.allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3))
    elif suffix == ".xyz":
        assert len(io.read_points(path)[0]) > 0
    elif suffix == ".pm":
        assert decimation.ProgressiveMesh.load(path).n_splits > 0
    else:
        raise AssertionError(f"no check for {path}")


@pytest.mark.parametrize("command, example", documented_examples(),
                         ids=[example for _, example in documented_examples()])
def test_documented_example_runs(inputs, command, example, monkeypatch, capsys):
    words = shlex.split(example)
    assert words[:2] == ["meshsmith", command]
    for output in outputs_of(words):
        target = inputs / output
        if target.is_file() and target.name != "mesh.pm":
            target.unlink()
    monkeypatch.chdir(inputs)
    status = cli.main(words[1:])                 # in-process: the same parser and commands, no start-up cost
    captured = capsys.readouterr()
    assert status == 0, (example, captured.err)
    outputs = outputs_of(words)
    assert outputs or command == "info"
    for output in outputs:
        check_valid(inputs / output, command)
    if command == "info" and "--json" in words:
        assert json.loads(captured.out)["n_faces"] == 320


# ---- bad usage: one line, no traceback, the right exit status -------------------------------

BAD_USAGE = [
    # (arguments, exit status, a word the message must hold)
    (["render", "{mesh}", "-o", "{tmp}/x"], 2, "no extension"),
    (["render", "{mesh}", "-o", "{tmp}/x.png", "--width", "100000000"], 2, "--width"),
    (["render", "{mesh}", "-o", "{tmp}/x.png", "--height", "0"], 2, "--height"),
    (["render", "{mesh}", "-o", "{tmp}/x.png", "--scalar", "z", "--range", "1", "0"], 2, "--range"),
    (["render", "{mesh}", "-o", "{tmp}/x.png", "--range", "0", "1"], 2, "--scalar"),
    (["render", "{mesh}", "-o", "{tmp}/missing/x.png"], 1, "does not exist"),
    (["curvature", "{mesh}", "-o", "{tmp}/c.jpg"], 2, ".png"),
    (["curvature", "{mesh}", "-o", "{tmp}/c.npy", "--range", "0", "1"], 2, "--range"),
    (["curvature", "{mesh}", "--kind", "mean", "--pointwise", "-o", "{tmp}/c.npy"], 2, "--pointwise"),
    (["decimate", "{mesh}", "-o", "{tmp}/d.obj", "--faces", "0"], 2, "--faces"),
    (["decimate", "{mesh}", "-o", "{tmp}/d.obj", "--error", "-1"], 2, "--error"),
    (["decimate", "{mesh}", "-o", "{tmp}/d.obj", "--ratio", "1.5"], 2, "--ratio"),
    (["decimate", "{mesh}", "-o", "{tmp}/d", "--faces", "10"], 2, "no extension"),
    (["normals", "{mesh}", "-o", "{tmp}/n.xyz", "--k", "0"], 2, "--k"),
    (["triangulate", "{tmp}/none.poly", "-o", "{tmp}/t.obj", "--min-angle", "50"], 2, "--min-angle"),
    (["info", "{tmp}/cloud.xyz"], 1, "meshsmith normals"),
    (["info", "{tmp}/missing.obj"], 1, "does not exist"),
    (["parametrize", "{mesh}", "-o", "{tmp}/p.obj", "--picture", "{tmp}/p.jpg"], 2, "--picture"),
    (["frobnicate"], 2, "invalid choice"),
    (["decimate", "{mesh}", "-o", "{tmp}/d.obj"], 2, "required"),
]


@pytest.mark.parametrize("args, status, word", BAD_USAGE, ids=[" ".join(a[:1] + a[3:]) for a, _, _ in BAD_USAGE])
def test_bad_usage_is_one_line(tmp_path, args, status, word):
    V, F = datasets.icosphere(1)
    io.write_mesh(tmp_path / "mesh.off", V, F)
    io.write_points(tmp_path / "cloud.xyz", V)
    args = [a.replace("{mesh}", str(tmp_path / "mesh.off")).replace("{tmp}", str(tmp_path)) for a in args]
    result = run(*args)
    lines = result.stderr.strip().splitlines()
    assert result.returncode == status, (args, result.stderr)
    assert len(lines) == 1 and lines[0].startswith("meshsmith: error:"), result.stderr
    assert word in lines[0] and "Traceback" not in result.stderr


def test_library_words_become_flags():
    from meshsmith import InputError
    from meshsmith.cli.common import user_message
    message = user_message(InputError("decimate: target_faces must be >= 0, got -1; max_error too"), "decimate")
    assert message == "decimate: --faces must be >= 0, got -1; --error too"
    assert "format=" not in user_message(InputError("x: no file extension to tell the format (pass format=...)"), "info")
    assert "--max-steiner-points" in user_message(InputError("refine: ...; raise the limit, lower min_angle"),
                                                 "triangulate")
    assert "--min-angle" in user_message(InputError("refine: raise the limit, lower min_angle"), "triangulate")


def test_closed_pipe_ends_quietly(tmp_path):
    V, F = datasets.icosphere(1)
    io.write_mesh(tmp_path / "mesh.off", V, F)
    read, write = os.pipe()
    os.close(read)                                   # `| head` that has already gone
    result = subprocess.run([sys.executable, "-m", "meshsmith", "info", str(tmp_path / "mesh.off")],
                            stdout=write, stderr=subprocess.PIPE, text=True)
    os.close(write)
    assert result.stderr == "" and result.returncode == 141


def test_missing_pillow_is_one_line(tmp_path):
    V, F = datasets.icosphere(1)
    io.write_mesh(tmp_path / "mesh.off", V, F)
    code = ("import sys; sys.modules['PIL'] = None\nfrom meshsmith.cli import main\n"
            f"sys.exit(main(['render', {str(tmp_path / 'mesh.off')!r}, '-o', {str(tmp_path / 'x.png')!r}]))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 1 and len(lines) == 1 and "pip install pillow" in lines[0]


def test_unexpected_error_is_one_line(monkeypatch, capsys):
    from meshsmith.cli import topology

    def broken(args):
        raise TypeError("something the code did not expect")

    monkeypatch.setattr(topology, "command_info", broken)
    assert cli.main(["info", "whatever.obj"]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "internal error" in lines[0] and "MESHSMITH_DEBUG" in lines[0]


def test_lod_above_the_finest_level_writes_the_full_mesh(inputs, tmp_path):
    out = tmp_path / "full.obj"
    result = run("lod", inputs / "mesh.pm", "--faces", "1000000", "-o", out)
    assert result.returncode == 0, result.stderr
    assert len(io.read_mesh(out)[1]) == 320
    result = run("lod", inputs / "mesh.pm", "--faces", "5", "-o", out)
    assert result.returncode == 1 and "--faces 5 is below the base mesh" in result.stderr


def test_normals_of_a_mesh_file_uses_its_vertices(inputs, tmp_path):
    out = tmp_path / "n.xyz"
    result = run("normals", inputs / "mesh.off", "-o", out, "--orient")
    assert result.returncode == 0, result.stderr
    P, N = io.read_points(out)
    V, _ = io.read_mesh(inputs / "mesh.off")
    np.testing.assert_array_equal(P, V)
    assert np.min(np.einsum("ij,ij->i", N, V / np.linalg.norm(V, axis=1, keepdims=True))) > 0.9  # outward


# ---- Ctrl-C ------------------------------------------------------------------------------

def _cpu_seconds(pid: int) -> float:
    """User + system CPU seconds a running process (all its threads) has used, from /proc."""
    with open(f"/proc/{pid}/stat") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def interrupt_and_wait(child: subprocess.Popen, timeout: float = 20.0) -> float:
    """Send SIGINT to `child` and reap it; return the CPU seconds it spent from the signal to its exit.

    CPU time, not wall time: on a shared 2-core machine at load 16-25 a process gets a tenth of a
    core, so wall time measures the load; the CPU a child burns before it stops measures how often
    the library polls for signals. A child that does not exit within `timeout` wall seconds fails."""
    before = _cpu_seconds(child.pid)
    child.send_signal(signal.SIGINT)
    deadline = time.monotonic() + timeout
    while True:
        pid, status, usage = os.wait4(child.pid, os.WNOHANG)
        if pid:
            child.returncode = os.waitstatus_to_exitcode(status)
            return usage.ru_utime + usage.ru_stime - before
        assert time.monotonic() < deadline, f"the child did not stop within {timeout} s of Ctrl-C"
        time.sleep(0.01)


def interrupt_on_terminal(command, marker: bytes, delay: float = 0.0):
    """Run `meshsmith COMMAND...` with stderr on a pseudo-terminal (so its bar draws), send SIGINT
    `delay` seconds after `marker` first shows there (however slow a loaded machine's start-up is),
    and return (exit status, the terminal's lines, CPU seconds from SIGINT to exit)."""
    leader, follower = pty.openpty()
    child = subprocess.Popen([sys.executable, "-m", "meshsmith", *map(str, command)], stdout=subprocess.PIPE,
                             stderr=follower)
    os.close(follower)
    shown = b""
    try:
        deadline = time.monotonic() + 60
        while marker not in shown and time.monotonic() < deadline and child.poll() is None:
            if select.select([leader], [], [], 0.1)[0]:
                shown += os.read(leader, 4096)
        assert marker in shown, shown
        time.sleep(delay)
        assert child.poll() is None, shown
        elapsed = interrupt_and_wait(child)
        while select.select([leader], [], [], 0.2)[0]:
            try:
                shown += os.read(leader, 4096)
            except OSError:                    # the terminal closed with the child
                break
    finally:
        child.kill()
        os.close(leader)
    return child.returncode, shown.decode().replace("\r\n", "\n").split("\n"), elapsed


def test_ctrl_c_stops_a_long_abf_within_a_second(tmp_path):
    V, F = datasets.icosphere(6)              # 81,920 faces: plain ABF runs for many seconds
    path = tmp_path / "sphere.off"
    io.write_mesh(path, V, F)
    # 1 s after the bar shows ABF's chart: inside the cut or the Newton steps
    status, lines, elapsed = interrupt_on_terminal(["parametrize", path, "--method", "abf", "-o", tmp_path / "uv.obj"],
                                                   b"abf: chart", delay=1.0)
    assert status == 130 and lines[-2:] == ["meshsmith: interrupted", ""], lines
    assert elapsed < 1.5, f"Ctrl-C took {elapsed:.2f} CPU s"


LIBRARY_ABF = """
import sys
from meshsmith import datasets, parametrization
V, F = datasets.icosphere(5)
cut = parametrization.cut_to_disk(V, F)
print("ready", flush=True)
try:
    for _ in range(100):                                  # long enough on any machine
        parametrization.abf(cut.V, cut.F, method="abf")   # no callback: Ctrl-C still reaches the Newton loop
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
print("finished", flush=True)
"""


def test_ctrl_c_reaches_the_library_abf_within_a_second():
    child = subprocess.Popen([sys.executable, "-c", LIBRARY_ABF], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    try:
        assert child.stdout.readline().strip() == "ready", child.stderr.read()
        time.sleep(1.0)
        elapsed = interrupt_and_wait(child)                  # its few lines of output fit the pipe
        stdout, stderr = child.stdout.read(), child.stderr.read()
    finally:
        child.kill()
    assert child.returncode == 130 and stdout.strip() == "interrupted", (stdout, stderr)
    assert elapsed < 1.5, f"Ctrl-C took {elapsed:.2f} CPU s inside abf"


def test_render_takes_negative_up_axes_and_prints_the_bar_range(inputs, tmp_path, capsys):
    from meshsmith import render
    out = tmp_path / "z.png"
    assert cli.main(["render", str(inputs / "mesh.off"), "-o", str(out), "--up", "-z", "--scalar", "z"]) == 0
    printed = capsys.readouterr().out
    V, _ = io.read_mesh(inputs / "mesh.off")
    low, high = render.scalar_range(V[:, 2], len(V))           # what the bar spans
    assert f"colour bar [{low:.6g}, {high:.6g}]" in printed
    below, above = int(np.sum(V[:, 2] < low)), int(np.sum(V[:, 2] > high))
    assert (f"{below} below" in printed) == (below > 0) and (f"{above} above" in printed) == (above > 0)
    assert cli.main(["render", str(inputs / "mesh.off"), "-o", str(out), "--scalar", "z",
                     "--range", str(V[:, 2].min()), str(V[:, 2].max())]) == 0
    assert "arrows" not in capsys.readouterr().out                 # nothing clipped: no arrow mentioned
