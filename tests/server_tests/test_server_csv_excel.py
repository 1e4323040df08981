"""Every CSV the server offers opens in German Excel as a table: `;` between the cells, UTF-8 with a byte-order
mark (umlauts intact), decimal commas, times in German local time; the instructor page's submissions export too."""

from __future__ import annotations

import csv
import datetime as dt
import io
import re
from zoneinfo import ZoneInfo

from server_helpers import BAD, GOOD, Api, auth

from server.export import excel_cell, excel_csv

BERLIN = ZoneInfo("Europe/Berlin")
GERMAN_TIME = re.compile(r"^\d\d\.\d\d\.\d{4} \d\d:\d\d:\d\d$")


def _table(content: bytes) -> list[list[str]]:
    assert content.startswith(b"\xef\xbb\xbf"), content[:20]
    first = content.decode("utf-8-sig").splitlines()[0]
    assert ";" in first and "," not in first  # Excel splits German CSV at ";" only
    return list(csv.reader(io.StringIO(content.decode("utf-8-sig")), delimiter=";"))


def test_the_submissions_export_is_a_german_excel_table(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    ex = api.exercise(owner, title_de="Übung mit Umlauten", stock={"min": [0, 0, -30], "max": [80, 70, 0]})
    good = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=auth(student)
    )
    api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": BAD}, headers=auth(student)
    )
    r = api.client.get("/api/v1/submissions/export.csv", params={"exercise": ex["slug"]}, headers=auth(owner))
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    header, *rows = _table(r.content)
    assert header == [
        "Abgabe",
        "Aufgabe",
        "Benutzer",
        "Lernplattform-Kennung",
        "Zeitpunkt",
        "Fehler",
        "Warnungen",
        "Bewegungen",
        "Punktzahl",
        "Höchstpunktzahl",
    ]
    assert len(rows) == 2 and all(row[2] == student["name"] for row in rows)
    created = dt.datetime.fromisoformat(good.json()["created_at"])
    row = next(row for row in rows if row[0] == str(good.json()["id"]))
    assert GERMAN_TIME.match(row[4]) and row[4] == created.astimezone(BERLIN).strftime("%d.%m.%Y %H:%M:%S")
    assert row[8] == str(good.json()["score"]) and row[9] == "100"


def test_every_csv_the_server_offers_is_for_german_excel(api: Api) -> None:
    teacher, student = api.user("instructor"), api.user()
    ex = api.exercise(teacher, stock={"min": [0, 0, -30], "max": [80, 70, 0]})
    api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=auth(student)
    )
    for path in ("/api/v1/submissions/export.csv", "/api/v1/results.csv"):
        r = api.client.get(path, headers=auth(teacher))
        assert r.status_code == 200, (path, r.text)
        assert len(_table(r.content)[0]) >= 4, path


def test_the_writer_speaks_german_excel() -> None:
    summer = dt.datetime(2026, 7, 1, 10, 0, 0, tzinfo=dt.UTC)
    winter = dt.datetime(2026, 12, 24, 10, 0, 0)  # stored without a zone: UTC
    assert excel_cell(summer) == "01.07.2026 12:00:00" and excel_cell(winter) == "24.12.2026 11:00:00"
    assert (
        excel_cell(87.5) == "87,5"
        and excel_cell(3) == 3
        and excel_cell(None) == ""
        and excel_cell(-0.0) == "0"
    )
    text = excel_csv(["Name", "Wert"], [["=cmd", 1.25], ["Müller", None]])
    assert text.startswith("\ufeff") and text.splitlines()[1:] == ["'=cmd;1,25", "Müller;"]
