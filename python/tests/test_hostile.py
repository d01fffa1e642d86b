"""Hostile input through the Python module (issue 47): a model that contains itself, values
nested without end, a broadcast view of a trillion items, a FIFO, an alias bomb, duplicate keys
and a second YAML document are bad input (velum.InputError, the command line's message), never
a crash or a hang. Each case runs in a child interpreter with a timeout, so that a regression
fails the test instead of killing or hanging the suite."""
import os
import subprocess
import sys
import textwrap

import pytest

import velum

PRELUDE = """
import sys
import numpy as np
import velum
def refused(f, *args):
    try:
        f(*args)
    except velum.InputError as e:
        print("InputError:", e.messages)
        return
    print("accepted")
"""


def child(code, tmp_path, timeout=30):
    """Runs `code` after PRELUDE in a fresh interpreter; its CompletedProcess."""
    script = tmp_path / "case.py"
    script.write_text(PRELUDE + textwrap.dedent(code))
    return subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=timeout, cwd=tmp_path, env=os.environ)


def test_a_model_that_contains_itself(tmp_path, square):
    p = child(f"""
        m = velum.load({str(square)!r})
        m["loads"] = [m._data]
        refused(velum.check, m)
        d = [1]
        d.append(d)
        m = velum.load({str(square)!r})
        m["title"] = d
        refused(velum.check, m)
    """, tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 2 and all(line.startswith("InputError:") for line in lines), p.stdout
    assert "loads[0]: contains itself" in lines[0]
    assert "title[1]: contains itself" in lines[1]


def test_values_nested_200000_deep(tmp_path, square):
    p = child(f"""
        v = 1.0
        for _ in range(200000):
            v = [v]
        m = velum.load({str(square)!r})
        m["title"] = v
        refused(velum.check, m)
        d = {{}}
        for _ in range(200000):
            d = {{"a": d}}
        m["title"] = d
        refused(velum.run, m)
    """, tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 2, p.stdout
    assert all(("title[0][0]" in line or "title.a.a" in line) and "nested more than 32 levels deep" in line
               for line in lines), p.stdout


def test_a_huge_broadcast_view(tmp_path, square):
    p = child(f"""
        m = velum.load({str(square)!r})
        m["mesh"]["nodes"] = np.broadcast_to(np.zeros(4), (10**12, 4))
        refused(velum.check, m)
        m["mesh"]["nodes"] = np.broadcast_to(np.zeros(1, dtype=np.int64), (2**40,))
        refused(velum.check, m)
    """, tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert len(lines) == 2 and all("mesh.nodes: an array of" in line for line in lines), p.stdout


def test_a_fifo_is_refused(tmp_path, run_cli):
    fifo = tmp_path / "model.yaml"
    os.mkfifo(fifo)
    p = child(f"refused(velum.load, {str(fifo)!r})", tmp_path, timeout=20)
    assert "not a regular file" in p.stdout, p.stdout + p.stderr
    cli = subprocess.run([os.environ["VELUM_EXE"], "check", str(fifo)], capture_output=True,
                         text=True, timeout=20)
    assert cli.returncode == 1 and "not a regular file" in cli.stderr


def billion_laughs(levels=12):
    lines = ["a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for i in range(1, levels):
        refs = ", ".join([f"*a{i - 1}"] * 10)
        lines.append(f"a{i}: &a{i} [{refs}]")
    return "\n".join(lines) + "\n"


def test_an_alias_bomb_loads_at_the_cost_of_its_text(tmp_path, square):
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text(billion_laughs() + square.read_text())
    p = child(f"""
        m = velum.load({str(bomb)!r})
        print("loaded", m["a11"][0] is m["a10"])
        refused(velum.check, m)
    """, tmp_path, timeout=30)
    assert p.returncode == 0, p.stderr
    assert p.stdout.splitlines()[0] == "loaded True", p.stdout
    assert "the model holds more than 134217728 values" in p.stdout, p.stdout
    cli = subprocess.run([os.environ["VELUM_EXE"], "check", str(bomb)], capture_output=True,
                         text=True, timeout=30)
    assert cli.returncode == 1 and "unknown key" in cli.stderr, cli.stderr


@pytest.mark.parametrize("text, message", [
    ("title: a\ntitle: b\n", "bad.yaml:2: title: the key 'title' is given twice (lines 1 and 2)"),
    ("title: a\n---\ntitle: b\n", "bad.yaml:2: a second YAML document"),
    ("title: a\n...\ntitle: b\n", "bad.yaml:3: a second YAML document"),
])
def test_load_refuses_what_the_command_line_refuses(tmp_path, run_cli, text, message):
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    with pytest.raises(velum.InputError) as e:
        velum.load(bad)
    assert any(message in m for m in e.value.messages), e.value.messages
    p = run_cli("check", bad)
    assert p.returncode == 1 and message in p.stderr, p.stderr
