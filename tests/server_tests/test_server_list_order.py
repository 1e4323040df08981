"""The exercise list's order compares the numbers in titles as numbers — and never fails on other digits."""

from __future__ import annotations

from server_helpers import Api, auth


def test_titles_with_superscript_and_other_digits_sort_without_error(api: Api) -> None:
    """'²' is a digit to Python's str.isdigit() but no number to int(): the list must still answer (found by the
    schemathesis run, GET /examples and GET /exercises answered 500)."""
    teacher = api.user("instructor")
    for title in ("Fläche 2²", "²", "Übung ١٢", "G23 Nuten", "G3 Kreis"):
        api.exercise(teacher, title_de=title)
    listed = api.client.get("/api/v1/exercises", headers=auth(teacher))
    assert listed.status_code == 200
    titles = [e["title_de"] for e in listed.json() if e["title_de"] in ("G23 Nuten", "G3 Kreis")]
    assert titles == ["G3 Kreis", "G23 Nuten"]
    assert api.client.get("/api/v1/examples").status_code == 200
