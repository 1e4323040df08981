"""CSV export: no cell a spreadsheet would run as a formula (OWASP: CSV injection), and who may name a
learner of a learning platform (external_user)."""

from __future__ import annotations

import csv
import io

import pytest
from server_helpers import GOOD, Api, auth, error_code

from server.export import csv_text

FORMULAS = [
    '=HYPERLINK("https://evil.example","Note")',
    "+1+2",
    "-2+3",
    "@SUM(A1:A2)",
    "\t=1+1",
    "\r=1+1",
    "\uff1dcmd|' /C calc'!A0",
]


def export(api: Api, who: dict[str, str], slug: str) -> list[dict[str, str]]:
    r = api.client.get("/api/v1/submissions/export.csv", params={"exercise": slug}, headers=auth(who))
    assert r.status_code == 200
    return list(csv.DictReader(io.StringIO(r.content.decode("utf-8-sig")), delimiter=";"))


def test_a_learner_id_that_looks_like_a_formula_is_exported_as_text(api: Api) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner)
    platform = api.api_key(["submissions:write", "submissions:read"])  # the operator's key
    for learner in FORMULAS:
        r = api.client.post(
            "/api/v1/submissions",
            json={"exercise": ex["slug"], "program": GOOD, "external_user": learner},
            headers=platform,
        )
        assert r.status_code == 201 and r.json()["external_user"] == learner  # stored as sent
    cells = sorted(row["Lernplattform-Kennung"] for row in export(api, owner, ex["slug"]))
    assert cells == sorted("'" + learner for learner in FORMULAS)


@pytest.mark.parametrize(
    "cell, written",
    [
        ("=1+1", "'=1+1"),
        ("+49 170", "'+49 170"),
        ("-x", "'-x"),
        ("@A1", "'@A1"),
        ("\tx", "'\tx"),
        ("\rx", "'\rx"),
        ("ok=1", "ok=1"),
        ("", ""),
        (-5, "-5"),
        (1.5, "1.5"),
        ("Müller", "Müller"),
    ],
)
def test_every_text_cell_is_escaped_and_numbers_stay(cell: object, written: str) -> None:
    rows = list(csv.reader(io.StringIO(csv_text(["a", "=b"], [[cell, "x"]]))))
    assert rows == [["a", "'=b"], [written, "x"]]


def test_only_keys_of_the_operator_instructors_and_admins_may_name_a_learner(api: Api) -> None:
    owner, student, admin = api.user("instructor"), api.user(), api.user("admin")
    ex = api.exercise(owner)
    scopes = ["submissions:write", "submissions:read"]
    body = {"exercise": ex["slug"], "program": GOOD, "external_user": "learner-42"}
    r = api.client.post("/api/v1/submissions", json=body, headers=api.api_key(scopes, owner=student))
    assert r.status_code == 403 and error_code(r) == "EXTERNAL_USER_FORBIDDEN"
    r = api.client.post(
        "/api/v1/submissions",
        json={**body, "external_user": None},
        headers=api.api_key(scopes, owner=student),
    )
    assert r.status_code == 201  # a student's own key submits for the student
    for key_owner in (owner, admin, None):
        r = api.client.post("/api/v1/submissions", json=body, headers=api.api_key(scopes, owner=key_owner))
        assert r.status_code == 201 and r.json()["external_user"] == "learner-42"
    learners = [row["Lernplattform-Kennung"] for row in export(api, owner, ex["slug"])]
    assert sorted(learners) == ["", "learner-42", "learner-42", "learner-42"]
