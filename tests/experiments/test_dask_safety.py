"""Dask executor: malformed addresses fail fast, TLS settings are checked, and a cluster
without workers is reported (with a timeout) instead of waiting silently."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from it2track.cli.main import main
from it2track.experiments.executors import (
    DaskExecutor,
    DaskSecurity,
    ExecutorError,
    check_scheduler_address,
    make_executor,
)


@pytest.mark.parametrize(
    "address",
    ["tcp://10.0.0.5:8786", "tls://scheduler.example:8786", "10.0.0.5:8786",
     "tcp://[::1]:8786", "ws://h:1", "inproc://192.0.2.2/1234/1"],
)
def test_well_formed_addresses_pass(address: str) -> None:
    assert check_scheduler_address(address) == address


@pytest.mark.parametrize(
    ("address", "needle"),
    [("foo", "the port is required"), ("tcp://foo", "the port is required"),
     ("http://h:80", "unknown protocol 'http'"), ("tcp://h:0", "port 0"),
     ("tcp://h:99999", "port 99999"), ("", "must be an address"),
     ("tcp://h:8786/extra", "not of the form"), ("tcp://user@h:1", "not of the form")],
)
def test_malformed_addresses_are_refused_before_connecting(address: str, needle: str) -> None:
    with pytest.raises(ExecutorError, match=needle):
        DaskExecutor(address)


def test_scheduler_without_port_is_a_fast_cli_error(tmp_path: Path) -> None:
    config = tmp_path / "s.toml"
    config.write_text('[sweep]\nseeds = 1\nnoise_std = 0.0\ntrajectories = "straight"\n'
                      '[[controllers]]\nkind = "flc"\n')
    # In a subprocess: the old failure stalled ~60 s in the Dask client's destructor.
    proc = subprocess.run(
        [sys.executable, "-m", "it2track", "sweep", "--config", str(config), "--out",
         str(tmp_path / "o"), "--scheduler", "foo"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert proc.returncode == 2
    assert "--scheduler" in proc.stderr and "'foo'" in proc.stderr
    assert "Traceback" not in proc.stderr and not (tmp_path / "o").exists()
    result = CliRunner().invoke(main, ["reproduce", "--quick", "--scheduler", "foo"])
    assert result.exit_code == 2 and "the port is required" in result.output


def test_tls_settings_are_checked(tmp_path: Path) -> None:
    cert = tmp_path / "client.pem"
    cert.write_text("not really a certificate")
    with pytest.raises(ExecutorError, match="needs its certificate"):
        DaskSecurity(key=str(cert))
    with pytest.raises(ExecutorError, match="does not exist"):
        DaskSecurity(ca_file=str(tmp_path / "missing.pem"))
    security = DaskSecurity(ca_file=str(cert), cert=str(cert))
    with pytest.raises(ExecutorError, match="not tls://HOST:PORT"):
        DaskExecutor("tcp://127.0.0.1:8786", security=security)
    with pytest.raises(ExecutorError, match="only to a Dask scheduler"):
        make_executor(workers=2, security=security)
    result = CliRunner().invoke(main, [
        "sweep", "--config", str(cert), "--out", str(tmp_path / "o"),
        "--scheduler", "tcp://127.0.0.1:8786", "--tls-cert", str(cert)])
    assert result.exit_code != 0
    assert "tls://" in result.output or "invalid TOML" in result.output


def test_a_scheduler_without_workers_is_reported_after_the_timeout() -> None:
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=":0") as c:
        with pytest.raises(ExecutorError, match=r"no Dask worker is connected .* \(waited 0.5 s\)"):
            DaskExecutor(c.scheduler_address, worker_timeout=0.5)


def _slow(x: int) -> int:
    time.sleep(0.2)
    return x


def test_workers_that_all_leave_mid_run_are_reported() -> None:
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:
        with DaskExecutor(cluster.scheduler_address, worker_timeout=0.5) as ex:
            ex.poll_interval = 0.1
            results = ex.imap_unordered(_slow, range(8))
            assert next(results) == (0, 0)
            cluster.scale(0)
            with pytest.raises(ExecutorError, match="every Dask worker left"):
                list(results)
