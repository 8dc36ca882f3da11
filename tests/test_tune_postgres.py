"""Several machines on one study: a real PostgreSQL server (Debian's), two `tune` processes.

The fixture starts the server the way a lab would: its own OS user (the server refuses to
run as root), a temporary data folder owned by that user, a free port on 127.0.0.1, trust
authentication for local connections only. It is skipped only when the binaries are absent.
"""

from __future__ import annotations

import glob
import json
import os
import pwd
import shutil
import socket
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

import optuna
import pytest

from tests.tune_helpers import scenario_file, tune, tune_process

PG_USER = "pgtest"
MERGE2 = "perception.merge.confirm_hits,perception.merge.min_length"


def _pg_bin() -> Path | None:
    found = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"))
    return Path(found[-1]).parent if found else None


def _as_server_user(cmd: list[str]) -> list[str]:
    """Root runs the server as its own user; anyone else runs it as themselves."""
    return ["runuser", "-u", PG_USER, "--", *cmd] if os.geteuid() == 0 else cmd


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def postgres_url() -> Iterator[str]:
    bin_dir = _pg_bin()
    if bin_dir is None:
        pytest.skip("PostgreSQL server binaries are not installed (/usr/lib/postgresql/*/bin/initdb)")
    if os.geteuid() == 0:
        try:
            pwd.getpwnam(PG_USER)
        except KeyError:
            subprocess.run(["useradd", "--system", "--no-create-home", "--shell", "/usr/sbin/nologin", PG_USER],
                           check=True)
    root = Path(tempfile.mkdtemp(prefix="pico-pgtest-"))
    data, sock, log = root / "data", root / "sock", root / "server.log"
    sock.mkdir()
    if os.geteuid() == 0:
        shutil.chown(root, PG_USER)
        shutil.chown(sock, PG_USER)
    port = _free_port()
    try:
        subprocess.run(_as_server_user([str(bin_dir / "initdb"), "-D", str(data), "-U", "postgres",
                                        "--auth=trust", "--no-sync", "-E", "UTF8"]),
                       check=True, capture_output=True)
        subprocess.run(_as_server_user([str(bin_dir / "pg_ctl"), "-D", str(data), "-l", str(log), "-w",
                                        "-o", f"-p {port} -k {sock} -c listen_addresses=127.0.0.1 -c fsync=off",
                                        "start"]), check=True, capture_output=True)
        yield f"postgresql://postgres@127.0.0.1:{port}/postgres"
    finally:
        if (data / "postmaster.pid").exists():
            subprocess.run(_as_server_user([str(bin_dir / "pg_ctl"), "-D", str(data), "-m", "fast", "-w", "stop"]),
                           capture_output=True)
        shutil.rmtree(root, ignore_errors=True)


def _load(url: str, name: str) -> optuna.Study:
    return optuna.load_study(study_name=name, storage=url.replace("postgresql://", "postgresql+psycopg://"))


def test_two_processes_share_one_postgresql_study(postgres_url, tmp_path):
    sc = scenario_file(tmp_path, poses=3)
    args = ["--scenarios", str(sc), "--params", MERGE2, "--storage", postgres_url, "--study", "shared",
            "--trials", "16"]
    procs = [tune_process(*args, "--out", str(tmp_path / f"m{i}"), "--seed", str(i)) for i in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [o[1] for o in outs]
    study = _load(postgres_url, "shared")
    trials = study.trials
    assert [t.number for t in trials] == list(range(len(trials)))  # no number twice, none lost
    assert len({t._trial_id for t in trials}) == len(trials)
    assert 16 <= len(trials) <= 17  # workers stop at the study's size (one may be starting as it fills)
    by_pid = {int(t.user_attrs["worker"].split(":")[1].split("/")[0]) for t in trials}
    assert by_pid == {p.pid for p in procs}  # both machines worked on it
    assert sum(bool(t.user_attrs.get("start")) for t in trials) == 1
    for out, _ in outs:  # each machine's report reads the whole study
        assert json.loads(out)["trials"] == len(trials)


def test_a_postgresql_study_adds_up_and_refuses_another_space(postgres_url, tmp_path, capsys):
    sc = scenario_file(tmp_path)
    args = ["--scenarios", str(sc), "--storage", postgres_url, "--study", "grow", "--out", str(tmp_path / "o")]
    assert tune(capsys, *args, "--params", MERGE2, "--trials", "3")[0] == 0
    code, j, _ = tune(capsys, *args, "--params", MERGE2, "--trials", "5")
    assert code == 0 and j["trials"] == 5
    code, _, err = tune(capsys, *args, "--params", "perception.identify.*", "--trials", "8")
    assert code == 2 and "another search space" in err
    assert len(_load(postgres_url, "grow").trials) == 5


def test_a_table_another_machine_created_meanwhile_is_retried_a_wrong_password_not():
    """Two machines opening one empty database race to create its tables; the loser sees a
    unique violation or (PostgreSQL) a DuplicateTable wrapped in a ProgrammingError — both are
    retried, once the tables are there; any other failure is reported at once."""
    from pico_studio.tuning.study import _created_meanwhile

    class IntegrityError(Exception):
        pass

    class ProgrammingError(Exception):
        pass

    dup = ProgrammingError('(psycopg.errors.DuplicateTable) relation "alembic_version" already exists')
    assert _created_meanwhile(dup) and _created_meanwhile(IntegrityError("duplicate key value"))
    assert not _created_meanwhile(Exception('password authentication failed for user "postgres"'))
