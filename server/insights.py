"""What a class got wrong in one assignment (issue 19): per exercise the most frequent diagnostics and the grading
criteria most students lost, with the block where most of them lost it ("12 of 20 lost the geometry criterion,
7 of them at G47") — what the instructor discusses the next morning.

Each student counts once per exercise, with the submission the results matrix shows: their best (the newest of
equal scores). The cost is bounded: the newest MAX_SUBMISSIONS submissions of the assignment are read in their light
columns (ids, authors, scores), no more (`capped` says when older ones were left out); program, diagnostics and
criteria are read for each student's best submission only, DETAILS_AT_ONCE at a time."""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Iterable, Iterator
from typing import Any, Literal

from pydantic import BaseModel, Field
from sqlalchemy.orm import Session

from server import courses, services
from server import repository as repo
from server.deps import Principal

MAX_SUBMISSIONS = 5000  # newest first; a class of 30 with 10 exercises and 15 tries each fits
DETAILS_AT_ONCE = 100  # best submissions whose program, diagnostics and grade are in memory at a time
TOP = 5  # diagnostics and criteria shown per exercise

# the rubric's criteria (core.exercises.DEFAULT_RUBRIC) as the instructor names them
CRITERION_NAMES: dict[str, tuple[str, str]] = {
    "geometry": ("Geometrie", "geometry"),
    "safety": ("Sicherheit", "safety"),
    "technology": ("Technologie (Schnittdaten)", "technology (cutting data)"),
    "syntax": ("Syntax", "syntax"),
    "tool_change": ("Werkzeugwechsel", "tool change"),
    "spindle_on": ("Spindel ein", "spindle on"),
    "compensation_off": ("Fräserradiuskorrektur aus", "cutter compensation off"),
    "safe_position": ("sichere Endposition", "safe end position"),
    "program_end": ("Programmende", "program end"),
}
# the block's feature: its first G word (G47, G1, G71 …), else its first M or T word
_G_WORD = re.compile(r"(?<![A-Z])G0*(\d{1,3})(?!\d)", re.IGNORECASE)
_MT_WORD = re.compile(r"(?<![A-Z])([MT])0*(\d{1,3})(?!\d)", re.IGNORECASE)


class Where(BaseModel):
    block: str = Field(
        description='The block\'s feature where most of them had it: its G word ("G47"), else its M or T word'
    )
    students: int = Field(description="How many of them had it there")


class DiagnosticInsight(BaseModel):
    code: str
    severity: Literal["error", "warning", "info"]
    message: str = Field(description="German; the most frequent wording among the students")
    message_en: str
    students: int = Field(description="Students whose submission has it (at least once)")
    where: Where | None


class CriterionInsight(BaseModel):
    id: str
    name: str
    name_en: str
    lost: int = Field(description="Students who did not get this criterion's full points")
    of: int = Field(description="Students with a graded submission to this exercise")
    points: int = Field(description="The criterion's points")
    where: Where | None


class ExerciseInsight(BaseModel):
    exercise: str
    title_de: str
    title_en: str | None
    students: int = Field(description="Students with a submission to this exercise")
    graded: int = Field(description="… of them graded")
    diagnostics: list[DiagnosticInsight]
    criteria: list[CriterionInsight]


class AssignmentInsights(BaseModel):
    assignment: int
    title: str
    basis: Literal["best"] = Field(
        description="Which submission of each student counts: the best (as in the results matrix)"
    )
    students: int = Field(description="Students in the course")
    scanned: int = Field(description="Submissions read")
    capped: bool = Field(description=f"More than {MAX_SUBMISSIONS} submissions: only the newest were read")
    exercises: list[ExerciseInsight]


def feature(program: str, line: int) -> str | None:
    """The feature of `line` (1-based) of `program`: "G47", "M6", "T1" … (comments after ';' or in parentheses
    are left out)."""
    lines = program.splitlines()
    if not 1 <= line <= len(lines):
        return None
    text = re.sub(r"\(.*?\)|;.*$", "", lines[line - 1])
    g = _G_WORD.search(text)
    if g:
        return f"G{int(g.group(1))}"
    mt = _MT_WORD.search(text)
    return f"{mt.group(1).upper()}{int(mt.group(2))}" if mt else None


def _where(places: Counter[str]) -> Where | None:
    if not places:
        return None
    block, n = min(places.items(), key=lambda kv: (-kv[1], kv[0]))
    return Where(block=block, students=n)


_SEVERITY_ORDER = {"error": 0, "warning": 1, "info": 2}


def _details(db: Session, ids: list[int]) -> Iterator[Any]:
    """Program, result and grade of these submissions (rows with .program, .result, .grading), a batch at a time."""
    for start in range(0, len(ids), DETAILS_AT_ONCE):
        yield from repo.submission_details(db, ids[start : start + DETAILS_AT_ONCE])


def _exercise_insight(slug: str, title_de: str, title_en: str | None, best: Iterable[Any]) -> ExerciseInsight:
    diag_students: Counter[str] = Counter()
    diag_places: dict[str, Counter[str]] = {}
    diag_texts: dict[str, Counter[tuple[str, str]]] = {}
    severity: dict[str, str] = {}
    lost: Counter[str] = Counter()
    lost_places: dict[str, Counter[str]] = {}
    points: dict[str, int] = {}
    order: dict[str, int] = {}
    graded = students = 0
    for s in best:
        students += 1
        seen: dict[str, dict[str, Any]] = {}
        for d in (s.result or {}).get("diagnostics", []):
            seen.setdefault(str(d.get("code")), d)  # the first one of a code in the program counts
        for code, d in seen.items():
            diag_students[code] += 1
            severity.setdefault(code, str(d.get("severity", "error")))
            diag_texts.setdefault(code, Counter())[
                (str(d.get("message", "")), str(d.get("message_en", "")))
            ] += 1
            place = feature(s.program, int(d.get("line") or 0))
            if place:
                diag_places.setdefault(code, Counter())[place] += 1
        if s.grading is None:
            continue
        graded += 1
        for i, c in enumerate(s.grading.get("criteria", [])):
            cid = str(c.get("id"))
            order.setdefault(cid, i)
            points[cid] = int(c.get("max_points", 0))
            if int(c.get("points", 0)) >= int(c.get("max_points", 0)):
                continue
            lost[cid] += 1
            lines = [int(n) for n in c.get("lines", []) if isinstance(n, int)]
            place = next((p for p in (feature(s.program, n) for n in lines) if p), None)
            if place:
                lost_places.setdefault(cid, Counter())[place] += 1
    diagnostics = []
    for code, n in sorted(
        diag_students.items(), key=lambda kv: (-kv[1], _SEVERITY_ORDER.get(severity[kv[0]], 3), kv[0])
    )[:TOP]:
        (de, en), _ = diag_texts[code].most_common(1)[0]
        diagnostics.append(
            DiagnosticInsight(
                code=code,
                severity=severity[code],  # type: ignore[arg-type]
                message=de,
                message_en=en,
                students=n,
                where=_where(diag_places.get(code, Counter())),
            )
        )
    criteria = []
    for cid, n in sorted(lost.items(), key=lambda kv: (-kv[1], -points.get(kv[0], 0), order.get(kv[0], 0)))[
        :TOP
    ]:
        de, en = CRITERION_NAMES.get(cid, (cid, cid))
        criteria.append(
            CriterionInsight(
                id=cid,
                name=de,
                name_en=en,
                lost=n,
                of=graded,
                points=points.get(cid, 0),
                where=_where(lost_places.get(cid, Counter())),
            )
        )
    return ExerciseInsight(
        exercise=slug,
        title_de=title_de,
        title_en=title_en,
        students=students,
        graded=graded,
        diagnostics=diagnostics,
        criteria=criteria,
    )


def assignment_insights(db: Session, principal: Principal, assignment_id: int) -> AssignmentInsights:
    """Instructors of the course and admins (students: 403, other instructors: 404). An ended exam's last drafts
    count once the background task has submitted them (a few seconds after the end)."""
    a = courses.assignment_for(db, principal, assignment_id, manage=True)
    students = {u.id for m, u in repo.members(db, a.course_id) if m.role == "student"}
    rows = repo.assignment_scores(db, a.id, MAX_SUBMISSIONS + 1)
    capped = len(rows) > MAX_SUBMISSIONS
    rows = rows[:MAX_SUBMISSIONS]
    by_key: dict[tuple[int, int], list[repo.Scored]] = {}
    for s in rows:
        if s.user_id in students:
            by_key.setdefault((s.exercise_id, s.user_id), []).append(s)
    out = []
    for slug in a.exercises:
        exercise = repo.exercise_by_slug(db, slug)
        if exercise is None:
            continue
        best = [
            services.best_of(subs).id  # type: ignore[arg-type]  # Scored has the score as its grading
            for (eid, _), subs in by_key.items()
            if eid == exercise.id
        ]
        out.append(_exercise_insight(slug, exercise.title_de, exercise.title_en, _details(db, best)))
    return AssignmentInsights(
        assignment=a.id,
        title=a.title,
        basis="best",
        students=len(students),
        scanned=len(rows),
        capped=capped,
        exercises=out,
    )
