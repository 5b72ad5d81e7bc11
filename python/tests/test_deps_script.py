"""tools/deps.sh: the apt-get command it prints for a user without root is
the one it runs as root, and it installs what the suites need (clang for the
C suite built with clang; no test needs git)."""
import os
import pathlib
import shutil
import stat
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _tool(d, name, body):
    p = d / name
    p.write_text("#!/bin/sh\n" + body + "\n")
    p.chmod(p.stat().st_mode | stat.S_IXUSR)


def _run(tmp_path, uid):
    """deps.sh in a copy of tools/, with stand-ins for dpkg-query (every
    package missing), id, sudo (no password-less sudo) and apt-get (logs)."""
    repo = tmp_path / f"repo{uid}"
    (repo / "tools").mkdir(parents=True)
    for f in ("deps.sh", "stage.sh"):
        shutil.copy2(ROOT / "tools" / f, repo / "tools" / f)
    fake = tmp_path / f"bin{uid}"
    fake.mkdir()
    log = tmp_path / f"apt{uid}.log"
    _tool(fake, "dpkg-query", "exit 1")
    _tool(fake, "id", f"echo {uid}")
    _tool(fake, "sudo", "exit 1")
    _tool(fake, "apt-get", f'echo "apt-get $*" >> "{log}"')
    env = dict(os.environ, PATH=f"{fake}{os.pathsep}{os.environ['PATH']}")
    r = subprocess.run(["bash", str(repo / "tools" / "deps.sh")], env=env, capture_output=True, text=True,
                       timeout=60)
    return r, (log.read_text().splitlines() if log.exists() else [])


def test_printed_command_is_the_one_run(tmp_path):
    user, none_run = _run(tmp_path, 1000)
    assert user.returncode == 1 and not none_run
    printed = user.stderr.split("run:", 1)[1].strip().splitlines()[0]
    update, install = (p.strip() for p in printed.split("&&"))
    root, ran = _run(tmp_path, 0)
    assert root.returncode == 0, root.stdout + root.stderr
    assert ran == [update, install.replace("DEBIAN_FRONTEND=noninteractive ", "")]
    assert "clang" in install.split() and "git" not in install.split()
