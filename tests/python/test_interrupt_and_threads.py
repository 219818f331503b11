"""Ctrl-C stops a run cleanly (rigidae.Interrupted, a KeyboardInterrupt,
with the records so far), and the GIL is released while a run integrates."""
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import rigidae
from conftest import HEAVY_TOP

# A run of ~minutes if left alone: the heavy top over 1000 s at a tight tolerance.
LONG = dict(t_end=1000.0, rtol=1e-10, atol=1e-10, output_step=1.0)


def test_ctrl_c_interrupts_a_run_and_keeps_its_records():
    script = textwrap.dedent(f"""
        import sys, time, rigidae
        print("ready", flush=True)
        try:
            rigidae.solve({HEAVY_TOP!r}, **{LONG!r})
        except rigidae.Interrupted as e:
            assert isinstance(e, KeyboardInterrupt)
            run = e.run
            print("interrupted", run.status, len(run.steps), run.final["t"], flush=True)
            sys.exit(0)
        sys.exit(3)
        """)
    env = dict(os.environ)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.5)  # well into the integration
    start = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 0, err
    words = out.split()
    assert words[0] == "interrupted" and words[1] == "interrupted"
    assert int(words[2]) > 0 and 0 < float(words[3]) < 1000.0
    assert time.monotonic() - start < 10  # stopped between steps, not at the end


def test_python_handler_is_back_after_a_run():
    rigidae.solve(HEAVY_TOP, t_end=0.05, record="none")
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_gil_released_while_integrating():
    done = threading.Event()
    result = {}

    def work():
        result["run"] = rigidae.solve(HEAVY_TOP, record="none", t_end=20.0, rtol=1e-11, atol=1e-11)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    ticks = 0
    # With the GIL held for the whole run this loop could not run until the end.
    while not done.is_set():
        time.sleep(0.002)
        ticks += 1
    t.join()
    wall = result["run"].summary["wall_time_s"]
    # The run must be long enough for the loop to matter (rigidae's own
    # vectors made it ~2x faster than when this test was written).
    assert wall > 0.1
    assert ticks >= 10, (ticks, wall)
