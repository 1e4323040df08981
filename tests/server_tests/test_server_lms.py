"""Authoring by upload and what learning platforms rely on: exercises imported from the exercise format
(validated, reference at full marks), idempotent submissions, and the grade as score, maximum and comment."""

from __future__ import annotations

from pathlib import Path

from server_helpers import Api, auth, error_code, unique

ROOT = Path(__file__).parents[2]


def exercise_file(slug: str, reference: str | None = None) -> str:
    """The built-in G2 exercise as an upload: a new id, the reference inline."""
    text = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.yaml").read_text(encoding="utf-8")
    program = reference or (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(
        encoding="utf-8"
    )
    text = text.replace("id: pal-05-g2-kreisbogen", f"id: {slug}")
    block = "reference: |\n" + "".join(f"  {line}\n" for line in program.splitlines())
    return text.replace("reference_file: pal-05-g2-kreisbogen.nc\n", block)


def test_import_an_exercise_file(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("upload-")
    r = api.client.post(
        "/api/v1/exercises/import",
        content=exercise_file(slug).encode(),
        headers={**auth(owner), "Content-Type": "application/yaml"},
    )
    assert r.status_code == 201, r.text
    assert r.json()["slug"] == slug and r.json()["gradable"] is True
    sub = api.client.post(
        "/api/v1/submissions",
        json={
            "exercise": slug,
            "program": exercise_file(slug).split("reference: |\n")[1].replace("\n  ", "\n").strip(),
        },
        headers=auth(student),
    )
    assert sub.status_code == 201 and sub.json()["score"] == 100
    again = api.client.post(
        "/api/v1/exercises/import",
        content=exercise_file(slug).encode(),
        headers={**auth(owner), "Content-Type": "application/yaml"},
    )
    assert again.status_code == 409 and error_code(again) == "EXERCISE_EXISTS"


def test_import_explains_what_is_wrong(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    bad = exercise_file(unique("upload-")).replace("feed: 150", "feed: -5")
    r = api.client.post("/api/v1/exercises/import", content=bad.encode(), headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "EXERCISE_INVALID"
    assert "cutting_data" in r.json()["error"]["message"]
    # a reference that does not run cleanly: an error in a block and no M30
    wrong_reference = exercise_file(
        unique("upload-"), reference="N10 T1 M6\nN20 S1200 F150 M3\nN30 G1 X1,5\n"
    )
    r = api.client.post("/api/v1/exercises/import", content=wrong_reference.encode(), headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "REFERENCE_NOT_CLEAN"
    assert "Zeile 3" in r.json()["error"]["message"] and "M30" in r.json()["error"]["message_en"]
    r = api.client.post(
        "/api/v1/exercises/import", content=exercise_file(unique("upload-")).encode(), headers=auth(student)
    )
    assert r.status_code == 403


def test_idempotent_submission_and_lms_result(api: Api) -> None:
    owner = api.user("instructor")
    slug = unique("upload-")
    assert (
        api.client.post(
            "/api/v1/exercises/import", content=exercise_file(slug).encode(), headers=auth(owner)
        ).status_code
        == 201
    )
    key = api.api_key(["submissions:read", "submissions:write", "exercises:read"])
    program = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(encoding="utf-8")
    flawed = program.replace(" M30", "")
    body = {"exercise": slug, "program": flawed, "external_user": "learner-7f3a"}
    first = api.client.post("/api/v1/submissions", json=body, headers={**key, "Idempotency-Key": "attempt-1"})
    assert first.status_code == 201
    lms = first.json()["lms"]
    assert (
        (lms["score"], lms["maximum"]) == (98, 100) and "M30" in lms["comment"] and "M30" in lms["comment_en"]
    )
    repeat = api.client.post(
        "/api/v1/submissions", json=body, headers={**key, "Idempotency-Key": "attempt-1"}
    )
    assert repeat.status_code == 200 and repeat.json()["id"] == first.json()["id"]
    listed = api.client.get("/api/v1/submissions", params={"exercise": slug}, headers=key).json()
    assert len(listed) == 1
    other = api.client.post(
        "/api/v1/submissions",
        json={**body, "program": program},
        headers={**key, "Idempotency-Key": "attempt-1"},
    )
    assert other.status_code == 409 and error_code(other) == "IDEMPOTENCY_CONFLICT"
    fresh = api.client.post(
        "/api/v1/submissions",
        json={**body, "program": program},
        headers={**key, "Idempotency-Key": "attempt-2"},
    )
    assert fresh.status_code == 201 and fresh.json()["lms"] == {
        "score": 100,
        "maximum": 100,
        "comment": "Alle Kriterien erfüllt.",
        "comment_en": "All criteria met.",
    }
    fetched = api.client.get(f"/api/v1/submissions/{first.json()['id']}", headers=key).json()
    assert fetched["lms"]["score"] == 98


def test_exercise_page_data_and_picture(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("upload-")
    assert (
        api.client.post(
            "/api/v1/exercises/import", content=exercise_file(slug).encode(), headers=auth(owner)
        ).status_code
        == 201
    )
    seen = api.client.get(f"/api/v1/exercises/{slug}", headers=auth(student)).json()
    assert seen["kind"] == "write"
    assert seen["cutting_data"] == [
        {"tool": 1, "speed": 1200.0, "cutting_speed": None, "feed": 150.0, "spindle": "M3"}
    ]
    assert seen["reference_program"] is None  # students never see the reference
    picture = api.client.get(f"/api/v1/exercises/{slug}/picture.png", headers=auth(student))
    assert picture.status_code == 200 and picture.headers["content-type"] == "image/png"
    assert picture.content.startswith(b"\x89PNG")
    assert api.client.get(f"/api/v1/exercises/{slug}/picture.png").status_code == 401
    help_ = api.client.get("/api/v1/dialects/beckhoff").json()
    assert {"#CHR", "G301"} <= {a["name"] for a in help_["addresses"]}
    assert next(c for c in help_["codes"] if c["name"] == "G302")["help_de"].startswith("Radius")
    assert api.client.get("/api/v1/dialects/klingon").status_code == 404
    for path in ("/", "/practice", "/login", "/instructor", f"/exercises/{slug}"):
        page = api.client.get(path)
        assert (
            page.status_code == 200 and page.text.startswith("<!doctype html>") and 'lang="de"' in page.text
        )
