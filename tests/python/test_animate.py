"""rigidae animate: a GIF and an MP4 of the four-bar with the frame count
asked for (Pillow, ffprobe), frames that differ as it moves, and a strobe
picture that is not blank."""
import shutil
import subprocess

import numpy as np
import pytest
from PIL import Image

from conftest import SOURCE, run_cli

FOUR_BAR = SOURCE / "problems" / "four_bar.toml"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("animate") / "run"
    code, _, stderr = run_cli("solve", FOUR_BAR, "--quiet", "--record", "grid", "--t-end", "1", "--out", out)
    assert code == 0, stderr
    return out


def test_gif_and_strobe(run):
    code, stdout, stderr = run_cli("animate", run, "--frames", "6", "--strobe", "4")
    assert code == 0, stderr
    gif = Image.open(run / "animation.gif")
    assert gif.n_frames == 6
    frames = []
    for i in (0, 5):
        gif.seek(i)
        frames.append(np.asarray(gif.convert("RGB"), dtype=float))
    # The four-bar covers a small part of the 3D box: 0.4 % of the pixels change (0 for equal frames).
    assert float((np.abs(frames[0] - frames[1]).sum(axis=2) > 60).mean()) > 0.002
    strobe = np.asarray(Image.open(run / "animation_strobe.png").convert("RGB"), dtype=float)
    assert float((strobe.sum(axis=2) < 600).mean()) > 0.01  # coloured shapes on white


@pytest.mark.skipif(shutil.which("ffprobe") is None, reason="Debian's ffmpeg is not installed")
def test_mp4_frame_count(run, tmp_path):
    mp4 = tmp_path / "four_bar.mp4"
    code, _, stderr = run_cli("animate", run, "--out", mp4, "--frames", "5", "--strobe", "2")
    assert code == 0, stderr
    p = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                        "stream=nb_read_frames", "-of", "csv=p=0", str(mp4)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert int(p.stdout.strip()) == 5
    assert (tmp_path / "four_bar_strobe.png").exists()


def test_bad_output_name(run, tmp_path):
    code, _, stderr = run_cli("animate", run, "--out", tmp_path / "a.avi")
    assert code == 2
    assert "the animation is a .gif or an .mp4" in stderr
    code, _, stderr = run_cli("animate", run, "--frames", "1.5")
    assert code == 2
    assert "--frames '1.5' must be an integer of at least 2" in stderr
