"""Campaigns on a TLS Dask scheduler: certificates from files the user names (CLI and
spec), refused without them."""

import subprocess

import pytest

from reciprocity.campaign import TLSFiles, build_report, load_spec, run_campaign
from reciprocity.cli import main
from reciprocity.errors import SearchError

#: A safety net against a hung openssl (it takes well under a second), not a speed check.
OPENSSL_HANG_S = 600
#: How long the refused client waits to connect (s): a refusal comes at once, this only
#: bounds the wait, generous enough that a busy machine still sees the refusal itself.
REFUSED_CONNECT_S = 10

SPEC = """\
seeds: 2
strategies: {random-walk: {n_steps: 3}}
scenarios: [otto-2d]
"""


def _openssl(*args, cwd):
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True, timeout=OPENSSL_HANG_S)


def _signed(name: str, ca: str, cwd) -> tuple[str, str]:
    """A key and a certificate signed by the CA `ca` (``ca.pem``, ``ca.key``)."""
    _openssl("req", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes",
             "-keyout", f"{name}.key", "-out", f"{name}.csr", "-subj", f"/CN={name}", cwd=cwd)
    _openssl("x509", "-req", "-in", f"{name}.csr", "-CA", f"{ca}.pem", "-CAkey", f"{ca}.key",
             "-CAcreateserial", "-out", f"{name}.pem", "-days", "1", cwd=cwd)
    return str(cwd / f"{name}.pem"), str(cwd / f"{name}.key")


def _ca(name: str, cwd) -> None:
    _openssl("req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
             "-nodes", "-keyout", f"{name}.key", "-out", f"{name}.pem", "-days", "1",
             "-subj", f"/CN={name}", cwd=cwd)


@pytest.fixture(scope="module")
def pki(tmp_path_factory):
    """A CA with certificates for the cluster and a client, and a stranger's CA and client."""
    d = tmp_path_factory.mktemp("pki")
    _ca("ca", d)
    _ca("other-ca", d)
    return {"ca": str(d / "ca.pem"), "node": _signed("node", "ca", d),
            "client": _signed("client", "ca", d), "stranger": _signed("stranger", "other-ca", d),
            "dir": d}


@pytest.fixture(scope="module")
def tls_scheduler(pki):
    """A TLS scheduler and one worker (threads of this process) on 127.0.0.1."""
    from distributed import LocalCluster
    from distributed.security import Security
    cert, key = pki["node"]
    sec = Security(tls_ca_file=pki["ca"], tls_scheduler_cert=cert, tls_scheduler_key=key,
                   tls_worker_cert=cert, tls_worker_key=key, tls_client_cert=cert,
                   tls_client_key=key, require_encryption=True)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tls://",
                      host="127.0.0.1", security=sec, dashboard_address=None) as cluster:
        assert cluster.scheduler_address.startswith("tls://127.0.0.1:")
        yield cluster.scheduler_address


def test_a_campaign_runs_through_a_tls_scheduler_with_cli_flags(tmp_path, pki, tls_scheduler,
                                                                 capsys):
    spec = tmp_path / "c.yaml"
    spec.write_text(SPEC)
    out = tmp_path / "out"
    cert, key = pki["client"]
    assert main(["campaign", str(spec), "--out", str(out), "--quiet", "--scheduler", tls_scheduler,
                 "--tls-ca-file", pki["ca"], "--tls-cert", cert, "--tls-key", key]) == 0
    assert "2 episodes run (0 failed)" in capsys.readouterr().out
    assert [r["runs"] for r in build_report(out).summary] == [2]


def test_the_spec_names_the_tls_scheduler_and_its_files(tmp_path, pki, tls_scheduler):
    spec = pki["dir"] / "spec.yaml"      # the certificate files relative to the spec
    spec.write_text(SPEC + f"scheduler:\n  address: {tls_scheduler}\n"
                    "  tls: {ca_file: ca.pem, cert: client.pem, key: client.key}\n")
    with pytest.raises(SearchError, match="confirm it with --scheduler spec"):
        run_campaign(load_spec(spec), tmp_path / "out", progress=False)     # never used unconfirmed
    assert not (tmp_path / "out").exists()
    result = run_campaign(load_spec(spec), tmp_path / "out", scheduler="spec", progress=False)
    assert (result.n_run, result.n_failed) == (2, 0)


def test_a_client_without_a_certificate_of_the_ca_is_refused(tmp_path, pki, tls_scheduler):
    spec = load_spec(_write(tmp_path, SPEC))
    cert, key = pki["stranger"]
    with pytest.raises(SearchError, match="TLS handshake .* failed"):
        run_campaign(spec, tmp_path / "a", scheduler=tls_scheduler, progress=False, timeout=REFUSED_CONNECT_S,
                     tls=TLSFiles(pki["ca"], cert, key))
    with pytest.raises(SearchError, match="needs TLS files"):
        run_campaign(spec, tmp_path / "b", scheduler=tls_scheduler, progress=False)
    with pytest.raises(SearchError, match="do not load"):   # a key that is not the certificate's
        run_campaign(spec, tmp_path / "c", scheduler=tls_scheduler, progress=False,
                     tls=TLSFiles(pki["ca"], pki["client"][0], key))
    assert not any((tmp_path / x / "campaign.json").exists() for x in "bc")


def _write(tmp_path, text):
    f = tmp_path / "c.yaml"
    f.write_text(text)
    return f
