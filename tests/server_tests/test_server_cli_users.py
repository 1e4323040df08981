"""`paltrainer admin create-user … --instructor NAME` and `paltrainer admin import-users class.csv --instructor NAME`."""

from __future__ import annotations

from pathlib import Path

import pytest

from core.cli import main
from server import repository as repo
from server.app import prepare_database
from server.config import Settings
from server.security import verify_password


@pytest.fixture
def data_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("PALTRAINER_DATA_DIR", str(tmp_path / "data"))
    monkeypatch.delenv("DATABASE_URL", raising=False)
    return tmp_path / "data"


def _users(data_dir: Path) -> dict[str, tuple[str, str | None, str]]:
    """name → (role, instructor's name, password hash)."""
    database = prepare_database(Settings(data_dir=data_dir, load_exercises=False))
    with database.session() as db:
        users = list(repo.list_users(db))
        names = {u.id: u.username for u in users}
        found = {
            u.username: (u.role, names.get(u.instructor_id) if u.instructor_id else None, u.password_hash)
            for u in users
        }
    database.engine.dispose()
    return found


def test_create_user_with_instructor(data_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["admin", "create-user", "lehrer", "--role", "instructor", "--password", "geheim123"]) == 0
    assert main(["admin", "create-user", "anna", "--password", "geheim123", "--instructor", "lehrer"]) == 0
    assert "lehrer" in capsys.readouterr().out
    assert main(["admin", "create-user", "ben", "--password", "geheim123", "--instructor", "anna"]) == 1
    assert "keine Lehrkraft" in capsys.readouterr().err
    assert main(["admin", "create-user", "ben", "--password", "geheim123", "--instructor", "niemand"]) == 1
    users = _users(data_dir)
    assert users["anna"][:2] == ("student", "lehrer") and "ben" not in users
    assert main(["admin", "create-user", "ben", "--password", "geheim123"]) == 0
    assert main(["admin", "set-instructor", "ben", "lehrer"]) == 0
    assert _users(data_dir)["ben"][1] == "lehrer"
    assert main(["admin", "set-instructor", "ben", "--none"]) == 0
    assert _users(data_dir)["ben"][1] is None
    assert main(["admin", "set-instructor", "niemand", "lehrer"]) == 1


def test_import_users(data_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["admin", "create-user", "lehrer", "--role", "instructor", "--password", "geheim123"]) == 0
    capsys.readouterr()
    csv_file = tmp_path / "klasse.csv"
    csv_file.write_bytes("\ufeffName;Passwort\r\ncarla;carlas-passwort\r\ndavid\r\n".encode())
    assert main(["admin", "import-users", str(csv_file), "--instructor", "lehrer"]) == 0
    out = dict(line.split(";") for line in capsys.readouterr().out.splitlines())
    assert out["carla"] == "" and len(out["david"]) >= 10
    users = _users(data_dir)
    assert users["carla"][:2] == ("student", "lehrer") and users["david"][:2] == ("student", "lehrer")
    assert verify_password(out["david"], users["david"][2]) and verify_password(
        "carlas-passwort", users["carla"][2]
    )
    # a bad list: the rows are named, nothing is made
    csv_file.write_text("emil\nMüller\n", encoding="utf-8")
    assert main(["admin", "import-users", str(csv_file), "--instructor", "lehrer"]) == 1
    assert "Zeile 2" in capsys.readouterr().err and "emil" not in _users(data_dir)
    assert main(["admin", "import-users", str(tmp_path / "fehlt.csv")]) == 2
