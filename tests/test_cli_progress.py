"""Progress of the commands whose library steps report none (render, curvature, info, convert):
stage progress read -> compute -> write on stderr, drawn only on a terminal; Ctrl-C is one line, 130."""
import io as stdio
import subprocess
import sys

import pytest
from test_cli import sphere_file  # noqa: F401  (the fixture)
from test_cli_examples import interrupt_on_terminal

from meshsmith import cli, datasets, io
from meshsmith.cli.common import ProgressBar, Stages


def recording_bar(module, monkeypatch):
    """Replace the ProgressBar a command module draws with one that records (fraction, stage)."""
    calls = []

    class RecordingBar(ProgressBar):
        def __call__(self, fraction, stage):
            calls.append((float(fraction), stage))
            return True

    monkeypatch.setattr(module, "ProgressBar", RecordingBar)
    return calls


@pytest.mark.parametrize("module, arguments, stages", [
    ("render", ["render", "{mesh}", "-o", "{tmp}/m.png"], ["reading", "rendering"]),
    ("render", ["render", "{mesh}", "-o", "{tmp}/m.png", "--scalar", "z"], ["reading", "scalar field", "rendering"]),
    ("geometry", ["curvature", "{mesh}", "-o", "{tmp}/k.png"], ["reading", "mean curvature", "rendering"]),
    ("geometry", ["curvature", "{mesh}", "--kind", "k1", "-o", "{tmp}/k.npy"], ["reading", "k1 curvature", "writing"]),
    ("topology", ["info", "{mesh}"], ["reading", "topology", "defects"]),
    ("topology", ["info", "{mesh}", "--json"], ["reading", "topology", "defects"]),
    ("io", ["convert", "{mesh}", "{tmp}/m.ply"], ["reading", "writing"]),
])
def test_commands_show_their_stages(sphere_file, tmp_path, monkeypatch, capsys, module, arguments, stages):
    calls = recording_bar(getattr(cli, module), monkeypatch)
    argv = [word.format(mesh=sphere_file, tmp=tmp_path) for word in arguments]
    assert cli.main(argv) == 0, capsys.readouterr().err
    shown = [stage.split(":")[0] for _, stage in calls]
    assert [stage for i, stage in enumerate(shown) if i == 0 or stage != shown[i - 1]] == stages
    fractions = [fraction for fraction, _ in calls]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0
    assert all(fraction < 1.0 for fraction in fractions[:-1])   # the line ends once, at the end


def test_info_defect_search_fills_its_stage(sphere_file, monkeypatch, capsys):
    calls = recording_bar(cli.topology, monkeypatch)
    assert cli.main(["info", str(sphere_file), "--intersections"]) == 0
    inside = [fraction for fraction, stage in calls if stage.startswith("defects: ")]
    assert inside and all(2 / 3 <= fraction < 1.0 for fraction in inside)   # the third stage's share


def test_a_forced_bar_draws_the_stages():
    stream = stdio.StringIO()
    stages = Stages(ProgressBar(width=10, force=True, stream=stream), ["reading", "computing", "writing"])
    for name in stages.names:
        stages.start(name)
        if name == "computing":
            stages.part()(0.5, "half")
    stages.done()
    text = stream.getvalue()
    assert "reading" in text and "computing: half" in text and "writing" in text
    assert "  0.0%" in text and " 50.0%" in text and "100.0%" in text and text.endswith("\n")
    assert text.count("\n") == 1
    with pytest.raises(ValueError):
        stages.start("reading")          # stages go forward only


def test_no_bar_when_stderr_is_not_a_terminal(sphere_file, tmp_path):
    for arguments in (["render", sphere_file, "-o", tmp_path / "m.png"], ["info", sphere_file],
                      ["curvature", sphere_file, "-o", tmp_path / "k.npy"],
                      ["convert", sphere_file, tmp_path / "m.obj"]):
        result = subprocess.run([sys.executable, "-m", "meshsmith", *map(str, arguments)], capture_output=True,
                                text=True)
        assert result.returncode == 0 and result.stderr == "", (arguments, result.stderr)


def test_on_a_terminal_the_bar_shows_the_stages_and_ctrl_c_ends_it_with_one_line(tmp_path):
    """stderr on a pseudo-terminal: the bar draws; SIGINT once it shows the computing stage ends the
    command within 1.5 CPU seconds, status 130, the bar's line ended and then `meshsmith: interrupted`."""
    V, F = datasets.icosphere(7)              # 327,680 faces: the quadric fit takes seconds
    path = tmp_path / "big.ply"
    io.write_mesh(path, V, F)
    status, lines, elapsed = interrupt_on_terminal(["curvature", path, "--kind", "k1", "-o", tmp_path / "k1.png"],
                                                   b"k1 curvature")
    assert any("reading" in line for line in lines), lines
    assert status == 130 and lines[-2:] == ["meshsmith: interrupted", ""], lines
    assert "[" in lines[-3] and "%" in lines[-3]          # the bar's line, ended before the message
    assert elapsed < 1.5, f"Ctrl-C took {elapsed:.2f} CPU s"
    assert not (tmp_path / "k1.png").exists()
