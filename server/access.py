"""Who may do what with an exercise, its drafts and its submissions at a moment — the one place that decides it.

The moments of an exercise for a trainee are: practice; in an exam of one of their courses that is upcoming,
running, ended and held (results not released), or released. Every route that touches an exercise, a draft or a
submission asks `decide` — REST, the live socket, the 3D view and its deviation, pictures, hints, the solution,
drafts, submissions, API keys and the learning platform's grade passback — with an action:

- live       live diagnostics: /check, /run, the live socket
- viz        the 3D view, /simulate, the picture of a program
- deviation  the comparison of a program's part with the reference (the 3D colours)
- hints      the exercise's hints
- solution   the reference program as the model solution
- reference  the reference and hidden criteria in the exercise's own data (its owner and admins)
- draft      saving a draft;  read_draft: reading it
- submit     a submission: to which assignment it goes, late, held, its limit
- grade      seeing the score and criteria of one's own practice submission (and passing it to a platform)

The rules (docs/server.md, "Exams"):
1. While an exam runs for a trainee, its settings switch features off for all their work (live, 3D, hints,
   solution), and without free practice every exercise outside the exam is refused.
2. Work on an exercise of a running exam belongs to that exam: its drafts (the exam starts from the start program,
   practice drafts never enter it, its drafts never leave it) and its submissions (counted against its limit,
   held until the release). Naming another assignment for it is refused.
3. From the moment an exercise is in an exam of a trainee's course until that exam's results are released, its
   reference, hints, model solution and deviation are withheld from them, and their practice submissions of it
   show no score or criteria (nor go to a platform's gradebook).
4. After an exam's end nothing more goes into it (EXAM_OVER); practice on its exercises goes on under rule 3.
5. Whose rules: the role in the exam's course decides, not the account's (an account that is an instructor
   elsewhere sits its course's exams as a student). An API key acts for its owner. Where the trainee is not
   known — nobody logged in, a key of the operator, a platform's learner named by `external_user` — an exercise of
   any running exam is refused and rule 3 holds for every unreleased exam.

Who sees an exercise at all (its page, the lists, the live check, 3D, pictures, sheets, drafts, submissions) — `sees`;
an exercise one does not see is "not found" for every action, alike for drafts and unknown names:
6. Admins see every exercise; authors their own (also archived ones).
7. An archived exercise ("deleted" with submissions) is seen by nobody else; its submissions stay.
8. Visibility "public" (and every built-in exercise): everyone. "courses": the members of every course the author
   teaches. "draft": only the author.
9. An exercise set in an assignment of a course is seen by that course's students from the assignment's opening
   on, whatever its visibility (an exam's exercise follows the exam's rules 1–4 from then on).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any, Literal

from sqlalchemy.orm import Session

from server import repository as repo
from server.errors import ApiError
from server.export import BERLIN
from server.models import Assignment, User, now
from server.schemas import utc

Action = Literal[
    "live", "viz", "deviation", "hints", "solution", "reference", "draft", "read_draft", "submit", "grade"
]
Phase = Literal["upcoming", "running", "held", "released", "open", "closed"]

# what an exam allows unless its settings say otherwise; practice allows everything, submissions unlimited (0)
EXAM_DEFAULTS: dict[str, Any] = {
    "live_diagnostics": False,
    "viz": False,
    "hints": False,
    "solution": False,
    "free_practice": False,
    "max_submissions": 1,
}
PRACTICE_DEFAULTS: dict[str, Any] = {
    "live_diagnostics": True,
    "viz": True,
    "hints": True,
    "solution": True,
    "free_practice": True,
    "max_submissions": 0,
}
# the setting of a running exam that switches an action off
_FEATURE: dict[str, str] = {
    "live": "live_diagnostics",
    "viz": "viz",
    "deviation": "viz",
    "hints": "hints",
    "solution": "solution",
}
_WITHHELD = ("hints", "solution", "reference", "deviation", "grade")  # rule 3


def settings_of(assignment: Assignment) -> dict[str, Any]:
    defaults = EXAM_DEFAULTS if assignment.mode == "exam" else PRACTICE_DEFAULTS
    return {**defaults, **{k: v for k, v in (assignment.settings or {}).items() if k in defaults}}


def end_of(assignment: Assignment) -> datetime:
    """The deadline; for an exam its end (start + duration)."""
    if assignment.mode == "exam" and assignment.duration_minutes:
        return utc(assignment.opens_at) + timedelta(minutes=assignment.duration_minutes)
    return utc(assignment.deadline)


@dataclass(frozen=True)
class Work:
    """An assignment as the rules see it (a snapshot: a live socket keeps it for a while)."""

    id: int
    title: str
    exam: bool
    exercises: tuple[str, ...]
    opens_at: datetime
    end: datetime
    released: bool
    late_accepted: bool
    settings: Mapping[str, Any]

    @classmethod
    def of(cls, a: Assignment) -> Work:
        return cls(
            id=a.id,
            title=a.title,
            exam=a.mode == "exam",
            exercises=tuple(a.exercises),
            opens_at=utc(a.opens_at),
            end=end_of(a),
            released=a.released_at is not None,
            late_accepted=a.late == "accept",
            settings=settings_of(a),
        )

    def phase(self, t: datetime) -> Phase:
        if t < self.opens_at:
            return "upcoming"
        if t < self.end:
            return "running" if self.exam else "open"
        if self.exam:
            return "released" if self.released else "held"
        return "closed"

    def has(self, slug: str | None) -> bool:
        return slug is not None and slug in self.exercises


@dataclass(frozen=True)
class Situation:
    """Who works and the assignments that concern them, read once per request (`situation`).

    `user_id` None: the trainee is not known (anonymous, an operator's key, a platform's learner); `assignments`
    then holds every unreleased exam of the server, else the assignments of the user's courses as a student."""

    user_id: int | None
    assignments: tuple[Work, ...]
    hidden: frozenset[str] = frozenset()  # the slugs of the exercises this trainee does not see (rules 6–9)

    def sees(self, slug: str) -> bool:
        return slug not in self.hidden

    def assignment(self, assignment_id: int) -> Work | None:
        return next((w for w in self.assignments if w.id == assignment_id), None)

    def running(self, t: datetime) -> list[Work]:
        return [w for w in self.assignments if w.exam and w.phase(t) == "running"]

    def guarding(self, slug: str | None) -> list[Work]:
        """The exams that withhold the exercise's reference: it is in them and their results are not released."""
        return [w for w in self.assignments if w.exam and not w.released and w.has(slug)]


@dataclass(frozen=True)
class Verdict:
    """What an allowed action is part of: the assignment the work goes to (drafts: only an exam keeps its own),
    late, held until the release, the number of submissions allowed (0: any)."""

    assignment: Work | None = None
    late: bool = False
    held: bool = False
    limit: int = 0

    @property
    def draft_scope(self) -> int | None:
        """The exam whose draft this is; None: the practice draft."""
        return self.assignment.id if self.assignment is not None and self.assignment.exam else None


def acting_user(principal: Any, external_user: str | None = None) -> User | None:
    """For whom a request works: the logged-in user, or the owner of the API key; None where the trainee is not
    known (anonymous, a key without owner, a platform's learner named by `external_user`)."""
    if external_user is not None and principal.api_key is not None:
        return None
    user: User | None = principal.user
    return user


def situation(db: Session, user: User | None, slug: str | None = None) -> Situation:
    """The situation of `user` (None: not known) for work on `slug` (None: no particular exercise)."""
    if user is not None:
        works = tuple(Work.of(a) for a in repo.student_assignments(db, user.id))
        return Situation(user.id, works, hidden_exercises(db, user, works))
    hidden = hidden_exercises(db, None, ())
    if slug is None:
        return Situation(None, (), hidden)  # free practice without an exercise: no exam concerns it
    return Situation(
        None, tuple(Work.of(a) for a in repo.unreleased_exams(db) if slug in a.exercises), hidden
    )


def unknown_situation(db: Session) -> Situation:
    """The situation of a trainee who is not known, for work on any exercise: every unreleased exam."""
    return Situation(
        None, tuple(Work.of(a) for a in repo.unreleased_exams(db)), hidden_exercises(db, None, ())
    )


def sees(
    user_id: int | None,
    role: str | None,
    course_instructors: set[int],
    opened: set[str],
    slug: str,
    owner_id: int | None,
    visibility: str,
    archived: bool,
) -> bool:
    """Rules 6–9: whether a user (None: not known) sees an exercise. `course_instructors`: the instructors of the
    user's courses; `opened`: the slugs set in opened assignments of the courses they are a student of."""
    if role == "admin" or (user_id is not None and owner_id == user_id):
        return True
    if archived:
        return False
    if visibility == "public" or slug in opened:
        return True
    return visibility == "courses" and owner_id is not None and owner_id in course_instructors


def hidden_exercises(
    db: Session,
    user: User | None,
    works: tuple[Work, ...],
    at: datetime | None = None,
) -> frozenset[str]:
    """The slugs of the exercises `user` does not see (read once per situation: only exercises that are not
    simply public are looked at)."""
    if user is not None and user.role == "admin":
        return frozenset()
    rows = repo.restricted_exercises(db)
    if not rows:
        return frozenset()
    t = at or now()
    instructors = repo.course_instructors_of(db, user.id) if user is not None else set()
    opened = {s for w in works if w.phase(t) != "upcoming" for s in w.exercises}
    uid, role = (user.id, user.role) if user is not None else (None, None)
    return frozenset(
        slug
        for slug, owner, visibility, archived in rows
        if not sees(uid, role, instructors, opened, slug, owner, visibility, archived)
    )


def require_seen(sit: Situation, slug: str) -> None:
    """EXERCISE_NOT_FOUND for an exercise the situation's trainee does not see (alike for unknown names)."""
    if not sit.sees(slug):
        raise ApiError("EXERCISE_NOT_FOUND", exercise=slug)


def german_time(t: datetime) -> str:
    return t.astimezone(BERLIN).strftime("%d.%m.%Y %H:%M")


def _running_error(exam: Work) -> ApiError:
    return ApiError("EXAM_RUNNING", end=exam.end.isoformat(), until=german_time(exam.end))


def decide(
    sit: Situation,
    action: Action,
    slug: str | None = None,
    named: int | None = None,
    at: datetime | None = None,
) -> Verdict:
    """Whether the action is allowed on the exercise `slug` (None: no exercise, as in free practice) for the
    assignment `named` by the request (drafts and submissions), at `at` (now); ApiError with the reason if not."""
    t = at or now()
    if slug is not None and action != "grade":  # the grade of a submission stays readable when archived
        require_seen(sit, slug)
    if sit.user_id is None:
        return _unknown(sit, action, slug, t)
    running = sit.running(t)
    own = next((w for w in running if w.has(slug)), None)  # the running exam this work belongs to (rule 2)
    off = switched_off(sit, action, t)
    if off is not None:  # rule 1
        raise _running_error(off)
    for exam in running:
        if (
            action not in ("grade", "read_draft")
            and not exam.has(slug)
            and not exam.settings["free_practice"]
        ):
            raise _running_error(exam)
    guarding = sit.guarding(slug)
    if action in _WITHHELD and guarding:  # rule 3; a running exam may allow its hints or solution itself
        feature = _FEATURE.get(action)
        if not (own is not None and action in ("hints", "solution") and feature and own.settings[feature]):
            raise ApiError("EXAM_WITHHELD", title=guarding[0].title)
    if action not in ("draft", "read_draft", "submit"):
        return Verdict()
    if named is not None:
        work = sit.assignment(named)
        if work is None:
            raise ApiError("ASSIGNMENT_NOT_FOUND", assignment=named)
        if not work.has(slug):
            raise ApiError("NOT_IN_ASSIGNMENT", exercise=slug, assignment=named)
        if own is not None and work.id != own.id:
            raise ApiError("EXAM_ELSEWHERE", title=own.title)
        return _entry(work, action, t)
    if own is not None:
        return _entry(own, action, t)
    if action == "submit":  # the open practice assignment with the exercise, the nearest deadline first
        open_ = sorted(
            (w for w in sit.assignments if not w.exam and w.has(slug) and w.phase(t) == "open"),
            key=lambda w: w.end,
        )
        if open_:
            return _entry(open_[0], action, t)
    return Verdict()


def switched_off(sit: Situation, action: Action, t: datetime) -> Work | None:
    """A running exam of the trainee whose settings switch the action off for all their work (rule 1), if any."""
    feature = _FEATURE.get(action)
    if feature is None:
        return None
    return next((w for w in sit.running(t) if not w.settings[feature]), None)


def _unknown(sit: Situation, action: Action, slug: str | None, t: datetime) -> Verdict:
    """Rule 5 for a trainee who is not known: the situation holds the unreleased exams with the exercise."""
    if slug is None:
        return Verdict()
    running = [w for w in sit.running(t) if w.has(slug)]
    if running and action != "grade":
        raise ApiError(
            "EXAM_EXERCISE_LOCKED", end=running[0].end.isoformat(), until=german_time(running[0].end)
        )
    if action in _WITHHELD and sit.guarding(slug):
        raise ApiError("EXAM_WITHHELD", title=sit.guarding(slug)[0].title)
    return Verdict()


def _entry(work: Work, action: Action, t: datetime) -> Verdict:
    """Work that goes into `work`: refused before it opens and, for an exam, after its end (reading the draft of
    an ended exam is fine: its page shows it); a practice assignment's late work as its policy says."""
    phase = work.phase(t)
    if phase == "upcoming":
        raise ApiError("ASSIGNMENT_NOT_OPEN", opens_at=work.opens_at.isoformat())
    if work.exam and phase in ("held", "released") and action != "read_draft":
        raise ApiError("EXAM_OVER", assignment=work.id)
    late = phase == "closed"
    if late and not work.late_accepted and action == "submit":
        raise ApiError("ASSIGNMENT_CLOSED", deadline=work.end.isoformat())
    return Verdict(
        assignment=work,
        late=late,
        held=work.exam and not work.released,
        limit=int(work.settings["max_submissions"] or 0),
    )


def allowed(sit: Situation, action: Action, slug: str | None = None, at: datetime | None = None) -> bool:
    try:
        decide(sit, action, slug, at=at)
    except ApiError:
        return False
    return True


def check(
    db: Session,
    principal: Any,
    action: Action,
    slug: str | None = None,
    named: int | None = None,
    external_user: str | None = None,
) -> Verdict:
    """`decide` for a request's principal, reading its situation."""
    user = acting_user(principal, external_user)
    return decide(situation(db, user, slug), action, slug, named)


def grade_visible(sit: Situation, submission: Any, slug: str) -> bool:
    """Whether the author of a submission (`sit` is theirs) may see its score and criteria now: an exam's once its
    results are released; any other while the exercise is not withheld (rule 3)."""
    if submission.held:
        return False
    work = sit.assignment(submission.assignment_id) if submission.assignment_id is not None else None
    if work is not None and work.exam:
        return True
    return allowed(sit, "grade", slug)
