"""The results table: trainees × exercises with the best score and the submissions' ids, as JSON and as a CSV
that German Excel opens as it is (`;`, UTF-8 with BOM, local time in Germany to the second, decimal comma)."""

from __future__ import annotations

import csv
import io
from datetime import datetime
from zoneinfo import ZoneInfo

from server_helpers import GOOD, Api, auth, builtin_exercise, reference_of

from server import repository as repo


def _manage(api: Api, student: dict[str, str], instructor: dict[str, str]) -> None:
    with api.app.state.db.session() as db:
        user, boss = repo.user_by_name(db, student["name"]), repo.user_by_name(db, instructor["name"])
        assert user is not None and boss is not None
        repo.set_instructor(db, user, boss.id)  # also enrols the student in the instructor's course


def test_results_json_and_csv(api: Api) -> None:
    teacher = api.user("instructor")
    anna, ben, idle = api.user(name="anna-" + api.user()["name"]), api.user(), api.user()
    for s in (anna, ben, idle):
        _manage(api, s, teacher)
    first = builtin_exercise(api, order=1, title={"de": "Erste", "en": "First"})
    second = builtin_exercise(api, order=2, title={"de": "=Zweite", "en": "Second"})  # a formula in a title

    def submit(who: dict[str, str], slug: str, program: str) -> dict[str, object]:
        r = api.client.post(
            "/api/v1/submissions", json={"exercise": slug, "program": program}, headers=auth(who)
        )
        assert r.status_code == 201
        return dict(r.json())

    low = submit(anna, first, GOOD)
    full = submit(anna, first, reference_of())
    again = submit(anna, first, GOOD)
    ben_second = submit(ben, second, GOOD)

    table = api.client.get("/api/v1/results", headers=auth(teacher)).json()
    assert [e["slug"] for e in table["exercises"]] == [first, second]
    rows = {t["username"]: t for t in table["trainees"]}
    assert set(rows) == {anna["name"], ben["name"], idle["name"]}
    cell = rows[anna["name"]]["results"][first]
    assert cell["best_score"] == 100 and cell["max_score"] == 100 and cell["best_submission"] == full["id"]
    assert cell["submissions"] == [again["id"], full["id"], low["id"]]
    assert second not in rows[anna["name"]]["results"] and rows[idle["name"]]["results"] == {}
    assert rows[ben["name"]]["results"][second]["best_score"] == ben_second["score"]
    assert rows[ben["name"]]["instructor"] == teacher["name"]

    r = api.client.get("/api/v1/results.csv", headers=auth(teacher))
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    assert "attachment" in r.headers["content-disposition"]
    assert r.content.startswith(b"\xef\xbb\xbf")
    text = r.content.decode("utf-8-sig")
    parsed = list(csv.reader(io.StringIO(text), delimiter=";"))
    header, body = parsed[0], parsed[1:]
    assert header[:4] == ["Benutzer", "Lehrkraft", "Aufgabe", "Titel"] and "Prozent" in header
    assert len(body) == 3 * 2  # every trainee × every exercise
    row = {(line[0], line[2]): dict(zip(header, line, strict=True)) for line in body}
    best = row[(anna["name"], first)]
    assert best["Beste Punktzahl"] == "100" and best["Prozent"] == "100,0" and best["Abgaben"] == "3"
    assert best["Beste Abgabe"] == str(full["id"])
    local = datetime.fromisoformat(str(full["created_at"])).astimezone(ZoneInfo("Europe/Berlin"))
    assert best["Zeitpunkt"] == local.strftime("%d.%m.%Y %H:%M:%S")
    ben_row = row[(ben["name"], second)]
    assert ben_row["Titel"] == "'=Zweite"  # not a formula in a spreadsheet
    score = int(str(ben_second["score"]))
    assert ben_row["Prozent"] == f"{score:.1f}".replace(".", ",") and "." not in ben_row["Prozent"]
    assert (
        row[(idle["name"], first)]["Beste Punktzahl"] == "" and row[(idle["name"], first)]["Abgaben"] == "0"
    )
