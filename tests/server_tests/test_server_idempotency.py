"""Retries of one submission with the same Idempotency-Key, sent at the same moment: one is made (201), every
other answer is that same submission (200) or a conflict (409), never a 500 — on SQLite and PostgreSQL."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

from server_helpers import GOOD, Api, auth, unique

RETRIES = 6
# long enough to grade that every retry has looked for the key before the first one is stored
SLOW = GOOD.replace(
    "N60 G0 Z50 M30\n", "".join(f"G1 X{i % 40} Y{i % 30}\n" for i in range(3000)) + "G0 Z50 M30\n"
)


def test_concurrent_retries_with_one_key_make_one_submission(api: Api) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner)
    key = api.api_key(["submissions:read", "submissions:write"])
    body = {"exercise": ex["slug"], "program": SLOW, "external_user": "learner-1"}
    headers = {**key, "Idempotency-Key": unique("retry-")}

    def submit(_: int) -> tuple[int, int | None]:
        r = api.client.post("/api/v1/submissions", json=body, headers=headers)
        return r.status_code, r.json().get("id")

    with ThreadPoolExecutor(RETRIES) as pool:
        answers = list(pool.map(submit, range(RETRIES)))
    codes = sorted(code for code, _ in answers)
    assert codes == [200] * (RETRIES - 1) + [201], answers
    assert len({sid for _, sid in answers}) == 1
    listed = api.client.get("/api/v1/submissions", params={"exercise": ex["slug"]}, headers=key).json()
    assert [s["id"] for s in listed] == [answers[0][1]]


def test_concurrent_retries_with_one_key_but_different_programs_conflict(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    ex = api.exercise(owner)
    headers = {**auth(student), "Idempotency-Key": unique("retry-")}
    programs = [SLOW.replace("X20", f"X{20 + i}") for i in range(RETRIES)]

    def submit(program: str) -> int:
        return api.client.post(
            "/api/v1/submissions", json={"exercise": ex["slug"], "program": program}, headers=headers
        ).status_code

    with ThreadPoolExecutor(RETRIES) as pool:
        codes = sorted(pool.map(submit, programs))
    assert codes == [201] + [409] * (RETRIES - 1), codes
    listed = api.client.get(
        "/api/v1/submissions", params={"exercise": ex["slug"]}, headers=auth(student)
    ).json()
    assert len(listed) == 1
