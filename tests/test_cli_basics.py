import subprocess
import sys

from catwalk.cli.main import main


def test_assets_are_unpacked_with_licence(mpfb2):
    assert (mpfb2 / "LICENSE.md").read_text().startswith("# Creative Commons CC0")
    assert (mpfb2 / "3dobjs" / "base.obj").stat().st_size > 1_000_000


def test_unknown_command_exits_2():
    res = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "no-such-command"],
                         capture_output=True, text=True)
    assert res.returncode == 2
    assert "invalid choice" in res.stderr
    assert "Traceback" not in res.stderr


def test_assets_command(capsys, mpfb2):
    assert main(["assets", "--quiet"]) == 0
    assert str(mpfb2) in capsys.readouterr().out


def test_a_misspelt_setting_is_named_and_the_test_variables_are_not(monkeypatch):
    """``CATWALK_DATABSE_URL`` would quietly give SQLite: it is reported; the tests' own
    variables (``CATWALK_TEST_*``, the fuzzers' ``CATWALK_FUZZ_*``) are not settings."""
    from catwalk.config import unknown_variables

    monkeypatch.setenv("CATWALK_DATABSE_URL", "postgresql://x")
    monkeypatch.setenv("CATWALK_FUZZ_EXAMPLES", "10000")
    monkeypatch.setenv("CATWALK_TEST_CHROMIUM", "/usr/bin/chromium")
    monkeypatch.setenv("CATWALK_STORAGE_DIR", "/tmp/x")
    assert unknown_variables() == ["CATWALK_DATABSE_URL"]
