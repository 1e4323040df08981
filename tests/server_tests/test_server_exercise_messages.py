"""Exercise uploads explain each wrong field in German (and separately in English), under one heading, never
with pydantic's English text; new format fields `solution` and `order` are read from the file."""

from __future__ import annotations

from pathlib import Path

from server_helpers import Api, auth, error_code, unique

ROOT = Path(__file__).resolve().parents[2]


def upload_text(slug: str) -> str:
    text = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.yaml").read_text(encoding="utf-8")
    program = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(encoding="utf-8")
    text = text.replace("id: pal-05-g2-kreisbogen", f"id: {slug}")
    return text.replace(
        "reference_file: pal-05-g2-kreisbogen.nc\n",
        "reference: |\n" + "".join(f"  {line}\n" for line in program.splitlines()),
    )


def test_upload_messages_per_field_in_german(api: Api) -> None:
    owner = api.user("instructor")
    bad = (
        upload_text("Kreis_Bogen")
        .replace("feed: 150", "feed: -5")
        .replace("dialect: pal-mill", "dialect: fanuc")
        + "farbe: rot\nsolution: sometimes\n"
    )
    r = api.client.post("/api/v1/exercises/import", content=bad.encode(), headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "EXERCISE_INVALID"
    error = r.json()["error"]
    de, en = error["message"], error["message_en"]
    assert de.startswith("Die Aufgabe ist ungültig: ") and de.count("ungültig") == 1
    assert "Feld `id`: nur Kleinbuchstaben, Ziffern und Bindestrich" in de
    assert "Feld `cutting_data[1].feed`: muss größer als 0 sein" in de
    assert "Feld `dialect`: erlaubt: 'pal-mill', 'sinumerik-iso', 'beckhoff' oder 'traub-tx8d'" in de
    assert "Feld `farbe`: gibt es im Aufgabenformat nicht" in de
    assert "Feld `solution`: erlaubt: 'never', 'after_submission' oder 'after_full_marks'" in de
    for english in ("should", "String", "Input", "exercise invalid", "Extra inputs"):
        assert english not in de, english
    assert en.startswith("The exercise is invalid: ") and "ungültig" not in en and "Feld" not in en
    assert "field `id`: only lower-case letters, digits and hyphens" in en
    fields = {p["field"]: p for p in error["details"]["errors"]}
    assert set(fields) >= {"id", "cutting_data[1].feed", "dialect", "farbe", "solution"}
    assert fields["id"]["message"].startswith("nur Kleinbuchstaben") and fields["id"][
        "message_en"
    ].startswith("only")


def test_upload_rule_and_yaml_messages(api: Api) -> None:
    owner = api.user("instructor")
    text = upload_text(unique("upload-")) + "rubric: [{id: geometry, points: 40}]\n"
    r = api.client.post("/api/v1/exercises/import", content=text.encode(), headers=auth(owner))
    assert r.status_code == 422
    assert (
        r.json()["error"]["message"]
        == "Die Aufgabe ist ungültig: Feld `rubric`: die Punkte müssen 100 ergeben (sind 40)"
    )
    assert r.json()["error"]["message_en"] == (
        "The exercise is invalid: field `rubric`: the points must add up to 100 (they are 40)"
    )
    r = api.client.post("/api/v1/exercises/import", content=b"id: [1\n", headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "EXERCISE_INVALID"
    assert r.json()["error"]["message"].startswith("Die Aufgabe ist ungültig: kein gültiges YAML (Zeile 2")
    assert (
        "not valid YAML" in r.json()["error"]["message_en"] and "kein" not in r.json()["error"]["message_en"]
    )


def test_upload_with_solution_order_and_hints(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("upload-")
    text = upload_text(slug) + "solution: never\norder: 7\nhints: [{de: Erst G2, en: G2 first}]\n"
    r = api.client.post("/api/v1/exercises/import", content=text.encode(), headers=auth(owner))
    assert r.status_code == 201, r.text
    seen = api.client.get(f"/api/v1/exercises/{slug}", headers=auth(student)).json()
    assert seen["solution"] == "never" and seen["order"] == 7 and seen["hint_count"] == 1
    r = api.client.get(f"/api/v1/exercises/{slug}/solution", headers=auth(student))
    assert r.status_code == 403 and error_code(r) == "SOLUTION_NEVER"
    assert api.client.get(f"/api/v1/exercises/{slug}/solution", headers=auth(owner)).status_code == 200
