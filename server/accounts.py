"""Accounts without the command line (issue 31): changing one's password, one-time passwords set by an instructor
or admin, deactivating and activating users, and self-registration with a course's join code.

The password rule is server/security.py's `password_problem` (the same for class lists, new users, changes and
sign-ups). Who is refused while a one-time password is unchanged: server/deps.py (`get_principal`); deactivated
users: server/deps.py too (their tokens, sessions and API keys), their login: server/routes/auth.py.
"""

from __future__ import annotations

from sqlalchemy import update
from sqlalchemy.orm import Session

from server import repository as repo
from server import services
from server.deps import Principal
from server.errors import ApiError
from server.models import Course, CourseMember, User, now
from server.schemas import UserOut
from server.security import hash_password, password_problem, verify_password


def check_new_password(password: str) -> None:
    """ApiError PASSWORD_RULE (422, naming the rule) unless `password` may be chosen."""
    problem = password_problem(password)
    if problem is not None:
        raise ApiError("PASSWORD_RULE", detail=problem[0], detail_en=problem[1])


def user_out(db: Session, user: User) -> UserOut:
    manager = repo.user_by_id(db, user.instructor_id) if user.instructor_id is not None else None
    return services.user_out(user, manager.username if manager else None)


def _set_password(db: Session, user: User, password: str, one_time: bool) -> None:
    """A new password; every token and session issued before stops working (the token version goes up)."""
    db.execute(
        update(User)
        .where(User.id == user.id)
        .values(
            password_hash=hash_password(password),
            must_change_password=one_time,
            token_version=User.token_version + 1,
        )
    )
    db.commit()
    db.refresh(user)


def change_password(db: Session, user: User, current: str, new: str) -> None:
    """The user's own change: the current password must be right (else 403 WRONG_PASSWORD), the new one follow
    the rule and differ from it. Clears the demand to change a one-time password."""
    if not verify_password(current, user.password_hash):
        raise ApiError("WRONG_PASSWORD")
    check_new_password(new)
    if new == current:
        raise ApiError(
            "PASSWORD_RULE",
            detail="es muss sich vom bisherigen Passwort unterscheiden",
            detail_en="it must differ from the current password",
        )
    _set_password(db, user, new, one_time=False)


def _teaches(db: Session, instructor: User, student: User) -> bool:
    """The student is the instructor's (managed by them) or a member of a course the instructor teaches."""
    if student.instructor_id == instructor.id:
        return True
    found = db.scalars(
        repo.taught_students(instructor.id).where(CourseMember.user_id == student.id).limit(1)
    ).first()
    return found is not None


def _acting_user(principal: Principal) -> User:
    """Account changes are made by logged-in users, not by API keys."""
    if principal.api_key is not None or principal.user is None:
        raise ApiError("FORBIDDEN")
    return principal.user


def reset_password(db: Session, principal: Principal, username: str) -> tuple[User, str]:
    """A one-time password for `username` (the user must change it at the next login): admins for anyone,
    instructors for the students they manage or teach. Every other name — unknown or not theirs — is the same
    404, so that nobody learns which accounts exist."""
    caller = _acting_user(principal)
    if caller.role not in ("instructor", "admin"):
        raise ApiError("FORBIDDEN")
    user = repo.user_by_name(db, username)
    allowed = user is not None and (
        caller.role == "admin" or (user.role == "student" and _teaches(db, caller, user))
    )
    if user is None or not allowed:
        raise ApiError("USER_NOT_FOUND", user=username)
    password = services.new_password()
    _set_password(db, user, password, one_time=True)
    return user, password


def _named(db: Session, username: str) -> User:
    user = repo.user_by_name(db, username)
    if user is None:
        raise ApiError("USER_NOT_FOUND", user=username)
    return user


def set_active(db: Session, principal: Principal, username: str, active: bool) -> UserOut:
    """Admins: deactivate (no login; every token, session and API key of the user stops working) or activate
    a user again. Not oneself."""
    user = _named(db, username)
    if user.id == principal.user_id:
        raise ApiError("OWN_ACCOUNT")
    if active:
        user.deactivated_at = None
        db.commit()
    elif user.deactivated_at is None:
        db.execute(
            update(User)
            .where(User.id == user.id)
            .values(deactivated_at=now(), token_version=User.token_version + 1)
        )
        db.commit()
        db.refresh(user)
    return user_out(db, user)


def signup(db: Session, code: str, username: str, password: str) -> User:
    """A visitor's own student account in the course with join code `code` (as POST /courses/join reads it):
    404 JOIN_CODE_INVALID for a code no course has (before anything else: no user-name oracle without a code),
    422 PASSWORD_RULE, 409 USER_EXISTS. The account remembers the course (User.signup_course_id)."""
    course: Course | None = repo.course_by_code(db, code.strip().upper())
    if course is None:
        raise ApiError("JOIN_CODE_INVALID")
    check_new_password(password)
    user = services.create_user(db, username, password, "student")
    user.signup_course_id = course.id
    db.commit()
    repo.add_member(db, course.id, user.id, "student")
    return user
