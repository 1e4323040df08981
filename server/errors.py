"""The API's errors: one catalogue of stable codes with German and English texts, and their JSON shape.

Every error response is `{"error": {"code", "message", "message_en", "details"}}` with an HTTP status
that means what it says; FastAPI's own validation and HTTP errors are converted to the same shape.
"""

from __future__ import annotations

import json
import logging
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel
from sqlalchemy.exc import DataError, IntegrityError
from starlette.exceptions import HTTPException as StarletteHTTPException

from server.repository import Duplicate

log = logging.getLogger("paltrainer.server")

# code → (HTTP status, German, English)
CATALOGUE: dict[str, tuple[int, str, str]] = {
    "VALIDATION": (422, "Die Anfrage ist ungültig: {detail}", "The request is invalid: {detail}"),
    "UNKNOWN_DIALECT": (422, "Unbekannter Dialekt »{dialect}«.", "Unknown dialect '{dialect}'."),
    "BAD_STOCK": (
        422,
        "Rohteil: zwei Ecken min und max mit je X, Y, Z; max größer als min in jeder Achse.",
        "Stock: two corners min and max with X, Y, Z each; max greater than min on every axis.",
    ),
    "NOT_AUTHENTICATED": (401, "Anmeldung erforderlich.", "Authentication required."),
    "BAD_CREDENTIALS": (401, "Benutzername oder Passwort ist falsch.", "Wrong user name or password."),
    "BAD_TOKEN": (401, "Das Token ist ungültig oder abgelaufen.", "The token is invalid or has expired."),
    "BAD_API_KEY": (
        401,
        "Der API-Schlüssel ist ungültig oder widerrufen.",
        "The API key is invalid or revoked.",
    ),
    "FORBIDDEN": (403, "Dafür fehlt die Berechtigung.", "You are not allowed to do this."),
    # accounts: passwords, resets, deactivation, self-registration (issue 31)
    "WRONG_PASSWORD": (403, "Das bisherige Passwort ist falsch.", "The current password is wrong."),
    "PASSWORD_RULE": (
        422,
        "Das neue Passwort ist nicht zulässig: {detail}.",
        "The new password is not allowed: {detail_en}.",
    ),
    "PASSWORD_CHANGE_REQUIRED": (
        403,
        (
            "Ihr Passwort wurde zurückgesetzt. Bitte legen Sie zuerst ein eigenes "
            "Passwort fest (Seite »Passwort ändern«)."
        ),
        ("Your password was reset. Please choose your own password first (page 'Change password')."),
    ),
    "ACCOUNT_DEACTIVATED": (
        403,
        (
            "Dieses Konto ist deaktiviert. Bitte wenden Sie sich an Ihre Ausbildungsstätte "
            "oder die Administration."
        ),
        "This account is deactivated. Please contact your training centre or the administrator.",
    ),
    "OWN_ACCOUNT": (
        409,
        "Das eigene Konto können Sie nicht deaktivieren und seine Rolle nicht ändern.",
        "You cannot deactivate your own account or change its role.",
    ),
    "VIZ_FOREIGN": (
        403,
        "Diese 3D-Ansicht gehört zu einer anderen Sitzung; bitte die Seite neu laden.",
        "This 3D view belongs to another session; please reload the page.",
    ),
    "VIZ_ELSEWHERE": (
        410,
        "Diese 3D-Ansicht lief auf einem anderen Server, der nicht mehr antwortet; bitte neu öffnen.",
        "This 3D view ran on another server that no longer answers; please open it again.",
    ),
    "MISSING_SCOPE": (
        403,
        "Dem API-Schlüssel fehlt der Bereich »{scope}«.",
        "The API key lacks the scope '{scope}'.",
    ),
    "FREE_PRACTICE_OFF": (
        401,
        "Freies Üben ist abgeschaltet; bitte anmelden.",
        "Free practice is switched off; please log in.",
    ),
    "NOT_FOUND": (404, "Nicht gefunden.", "Not found."),
    "EXERCISE_NOT_FOUND": (404, "Aufgabe »{exercise}« nicht gefunden.", "Exercise '{exercise}' not found."),
    "SUBMISSION_NOT_FOUND": (
        404,
        "Abgabe {submission} nicht gefunden.",
        "Submission {submission} not found.",
    ),
    "USER_NOT_FOUND": (404, "Benutzer »{user}« nicht gefunden.", "User '{user}' not found."),
    "API_KEY_NOT_FOUND": (404, "API-Schlüssel {key} nicht gefunden.", "API key {key} not found."),
    "METHOD_NOT_ALLOWED": (405, "Diese Methode ist hier nicht erlaubt.", "Method not allowed here."),
    "EXERCISE_EXISTS": (
        409,
        "Eine Aufgabe mit der Kennung »{exercise}« gibt es schon.",
        "An exercise with the slug '{exercise}' already exists.",
    ),
    "USER_EXISTS": (409, "Den Benutzer »{user}« gibt es schon.", "The user '{user}' already exists."),
    "CONFLICT": (
        409,
        "Das gibt es schon (gleichzeitige Anfrage); bitte neu laden.",
        "This already exists (a concurrent request); please reload.",
    ),
    "EXTERNAL_USER_FORBIDDEN": (
        403,
        (
            "Nur API-Schlüssel des Betreibers, einer Lehrkraft oder eines Admins dürfen "
            "»external_user« setzen."
        ),
        "Only API keys of the operator, an instructor or an admin may set 'external_user'.",
    ),
    "OUT_OF_RANGE": (
        422,
        (
            "Ein Wert lässt sich nicht speichern: außerhalb des Bereichs der Datenbank oder mit "
            "einem unzulässigen Zeichen."
        ),
        "A value cannot be stored: outside the database's range, or with a character it does not allow.",
    ),
    "IDEMPOTENCY_CONFLICT": (
        409,
        "Dieser Idempotency-Key wurde schon für eine andere Abgabe verwendet.",
        "This Idempotency-Key was already used for a different submission.",
    ),
    "EXERCISE_REQUIRED": (
        422,
        "Dafür muss eine Aufgabe angegeben sein (Feld »exercise«).",
        "This needs an exercise (field 'exercise').",
    ),
    "EXERCISE_INVALID": (422, "Die Aufgabe ist ungültig: {detail}", "The exercise is invalid: {detail_en}"),
    "HINT_NOT_FOUND": (
        404,
        "Die Aufgabe hat keinen Tipp {hint} (sie hat {count}).",
        "The exercise has no hint {hint} (it has {count}).",
    ),
    "SOLUTION_NEVER": (
        403,
        "Für diese Aufgabe wird keine Musterlösung gezeigt.",
        "This exercise does not show its reference solution.",
    ),
    "SOLUTION_AFTER_SUBMISSION": (
        403,
        "Die Musterlösung gibt es nach der ersten Abgabe.",
        "The reference solution is shown after the first submission.",
    ),
    "SOLUTION_AFTER_FULL_MARKS": (
        403,
        "Die Musterlösung gibt es, sobald eine Abgabe die volle Punktzahl erreicht.",
        "The reference solution is shown once a submission scores full marks.",
    ),
    "DRAFTS_USERS_ONLY": (
        403,
        "Entwürfe werden nur für angemeldete Benutzer gespeichert, nicht für API-Schlüssel.",
        "Drafts are kept for logged-in users only, not for API keys.",
    ),
    "NOT_AN_INSTRUCTOR": (422, "»{user}« ist keine Lehrkraft.", "'{user}' is not an instructor."),
    "NOT_A_STUDENT": (
        422,
        ("»{user}« ist kein Schülerkonto; Lehrkräfte und Admins werden nicht als Schüler eingetragen."),
        "'{user}' is not a student account; instructors and admins are not enrolled as students.",
    ),
    "CLASS_LIST_INVALID": (
        422,
        "Die Klassenliste ist ungültig: {detail}",
        "The class list is invalid: {detail_en}",
    ),
    "REFERENCE_NOT_CLEAN": (
        422,
        ("Die Musterlösung erreicht nicht die volle Punktzahl ({score} von {max_score}): {detail}"),
        "The reference does not score full marks ({score} of {max_score}): {detail_en}",
    ),
    "DRAWING_INVALID": (
        422,
        "Die Zeichnung wird nicht angenommen: {detail}",
        "The drawing is refused: {detail_en}",
    ),
    "DRAWING_TOO_LARGE": (
        413,
        "Die Zeichnung ist zu groß ({size} Bytes, höchstens {limit}).",
        "The drawing is too large ({size} bytes, at most {limit}).",
    ),
    "EXERCISE_NOT_COPYABLE": (
        403,
        "Kopieren lassen sich eingebaute und eigene Aufgaben.",
        "Built-in exercises and one's own can be duplicated.",
    ),
    "EXERCISE_HAS_SUBMISSIONS": (
        409,
        "Die Aufgabe hat Abgaben und kann nicht gelöscht werden.",
        "The exercise has submissions and cannot be deleted.",
    ),
    # courses, assignments and exams (issue 19)
    "COURSE_NOT_FOUND": (404, "Klasse {course} nicht gefunden.", "Course {course} not found."),
    "JOIN_CODE_INVALID": (
        404,
        "Zu diesem Beitrittscode gibt es keine Klasse.",
        "No course has this join code.",
    ),
    "ASSIGNMENT_NOT_FOUND": (
        404,
        "Auftrag {assignment} nicht gefunden.",
        "Assignment {assignment} not found.",
    ),
    "NOT_IN_ASSIGNMENT": (
        422,
        "Die Aufgabe »{exercise}« gehört nicht zu Auftrag {assignment}.",
        "Exercise '{exercise}' is not part of assignment {assignment}.",
    ),
    "ASSIGNMENT_TIMES": (422, "Zeiten des Auftrags: {detail}", "Times of the assignment: {detail_en}"),
    "ASSIGNMENT_NOT_OPEN": (
        409,
        "Der Auftrag ist noch nicht freigegeben (ab {opens_at}).",
        "The assignment is not open yet (from {opens_at}).",
    ),
    "ASSIGNMENT_CLOSED": (
        409,
        ("Die Abgabefrist ist abgelaufen ({deadline}); verspätete Abgaben werden nicht angenommen."),
        "The deadline has passed ({deadline}); late submissions are not accepted.",
    ),
    "ASSIGNMENT_SUBMITTED": (
        409,
        ("Für »{exercise}« ist in diesem Auftrag nur {limit} Abgabe erlaubt; sie ist schon erfolgt."),
        "Only {limit} submission is allowed for '{exercise}' in this assignment; it was made.",
    ),
    "EXAM_OVER": (
        403,
        (
            "Die Prüfungszeit ist abgelaufen; Abgaben und Entwürfe werden nicht mehr angenommen. Der "
            "letzte gespeicherte Entwurf wurde abgegeben."
        ),
        (
            "The exam time is over; submissions and drafts are no longer accepted. The last saved draft "
            "was submitted."
        ),
    ),
    "EXAM_RUNNING": (
        403,
        "Während der Prüfung (bis {until} Uhr) ist das nicht erlaubt.",
        "This is not allowed while the exam runs (until {until}).",
    ),
    "EXAM_ELSEWHERE": (
        403,
        (
            "Diese Aufgabe gehört gerade zur laufenden Prüfung »{title}«: Entwürfe und Abgaben gehen "
            "nur dorthin."
        ),
        "This exercise belongs to the running exam '{title}': drafts and submissions go there only.",
    ),
    "EXAM_WITHHELD": (
        403,
        (
            "Diese Aufgabe ist Teil der Prüfung »{title}«: Musterlösung, Tipps, der Vergleich mit "
            "der Musterlösung und die Bewertung von Übungsabgaben gibt es erst, wenn die Ergebnisse "
            "freigegeben sind."
        ),
        (
            "This exercise is part of the exam '{title}': the model solution, hints, the comparison with "
            "it and the grades of practice submissions follow once the results are released."
        ),
    ),
    "EXAM_EXERCISE_LOCKED": (
        403,
        (
            "Diese Aufgabe wird gerade in einer Prüfung bearbeitet; ohne Anmeldung ist sie "
            "bis zu deren Ende ({until} Uhr) gesperrt."
        ),
        (
            "This exercise is being worked on in an exam; without logging in it is locked until "
            "the exam's end ({until})."
        ),
    ),
    "NOT_GRADED": (
        409,
        "Abgabe {submission} ist nicht bewertet; ihre Punktzahl lässt sich nicht ändern.",
        "Submission {submission} is not graded; its score cannot be changed.",
    ),
    "OVERRIDE_OUT_OF_RANGE": (
        422,
        "Die Punktzahl {score} liegt über der Höchstpunktzahl {max_score}.",
        "The score {score} is above the maximum of {max_score}.",
    ),
    "EXAM_NOT_OVER": (
        409,
        "Die Ergebnisse lassen sich erst nach dem Ende der Prüfung freigeben.",
        "The results can be released only after the exam has ended.",
    ),
    # LTI grades and roster (issue 20)
    "LTI_NO_ROSTER": (
        409,
        (
            "Diese Klasse ist mit keinem Kurs einer Lernplattform verbunden, der eine Teilnehmerliste "
            "anbietet; zuerst PAL Trainer aus dem Kurs der Lernplattform als Lehrkraft starten."
        ),
        (
            "This course is linked to no learning-platform course that offers a roster; launch PAL "
            "Trainer from the platform's course as an instructor first."
        ),
    ),
    "LTI_PLATFORM_ERROR": (
        502,
        "Die Lernplattform hat nicht wie erwartet geantwortet: {detail}",
        "The learning platform did not answer as expected: {detail_en}",
    ),
    "LTI_SCORE_NOT_FOUND": (
        404,
        "Notenübertragung {score} nicht gefunden.",
        "Grade passback {score} not found.",
    ),
    "LTI_SCORE_NOT_FAILED": (
        409,
        "Nur eine aufgegebene Notenübertragung lässt sich erneut senden.",
        "Only a grade passback that was given up can be sent again.",
    ),
    "BODY_TOO_LARGE": (
        413,
        "Die Anfrage ist zu groß ({size} Bytes, höchstens {limit}).",
        "The request is too large ({size} bytes, at most {limit}).",
    ),
    "PROGRAM_TOO_LARGE": (
        413,
        "Das Programm ist zu lang ({size} Zeichen, höchstens {limit}).",
        "The program is too long ({size} characters, at most {limit}).",
    ),
    "RATE_LIMITED": (
        429,
        "Zu viele Anfragen; bitte in {retry_after} s erneut versuchen.",
        "Too many requests; please retry in {retry_after} s.",
    ),
    "TOO_MANY_JOBS": (
        429,
        (
            "Sie haben schon {limit} rechenintensive Anfragen in Arbeit (PDF, Bilder, Zeichnungen, "
            "Abgaben, Simulation, 3D-Ansicht). Bitte warten Sie, bis eine davon fertig ist, und "
            "versuchen Sie es dann erneut."
        ),
        (
            "You already have {limit} heavy requests in progress (PDF, pictures, drawings, submissions, "
            "simulation, 3D view). Please wait until one of them has finished, then try again."
        ),
    ),
    "TIME_LIMIT": (
        503,
        "Die Berechnung hat das Zeitlimit von {seconds} s überschritten.",
        "The computation exceeded the time limit of {seconds} s.",
    ),
    "NOT_READY": (503, "Der Server ist nicht bereit: {detail}", "The server is not ready: {detail}"),
    "PDF_UNAVAILABLE": (
        503,
        "PDF-Aufgabenblätter sind auf diesem Server nicht verfügbar: {detail}",
        "PDF task sheets are not available on this server: {detail_en}",
    ),
    "WORKER_FAILED": (
        503,
        (
            "Der Rechenprozess ist bei diesem Programm zweimal abgebrochen; bitte das Programm "
            "prüfen oder später erneut versuchen."
        ),
        "The worker process failed twice on this program; check the program or retry later.",
    ),
    "BUSY": (
        503,
        "Alle Rechenprozesse sind seit {seconds} s belegt; bitte gleich erneut versuchen.",
        "Every worker process has been busy for {seconds} s; please retry shortly.",
    ),
    "INTERNAL": (500, "Interner Fehler (Anfrage {request_id}).", "Internal error (request {request_id})."),
}


class ErrorDetail(BaseModel):
    code: str
    message: str
    message_en: str
    details: dict[str, Any] = {}


class ErrorBody(BaseModel):
    """The body of every error response."""

    error: ErrorDetail


class ApiError(Exception):
    """An error with a stable code from the catalogue; the handler turns it into JSON."""

    def __init__(self, code: str, headers: dict[str, str] | None = None, **params: Any) -> None:
        status, de, en = CATALOGUE[code]
        super().__init__(code)
        self.code, self.status, self.params, self.headers = code, status, params, headers
        self.message, self.message_en = de.format(**params), en.format(**params)

    def body(self) -> dict[str, Any]:
        return {
            "error": {
                "code": self.code,
                "message": self.message,
                "message_en": self.message_en,
                "details": {k: v for k, v in self.params.items() if k != "detail"},
            }
        }


class ErrorResponse(JSONResponse):
    """JSON that always encodes: an error may quote the request, and a request may hold a lone surrogate."""

    def render(self, content: Any) -> bytes:
        return json.dumps(content, ensure_ascii=False, allow_nan=False, separators=(",", ":")).encode(
            "utf-8", errors="replace"
        )


def error_response(err: ApiError) -> JSONResponse:
    return ErrorResponse(err.body(), status_code=err.status, headers=err.headers)


_DESCRIPTIONS = {
    401: "Not authenticated",
    403: "Forbidden",
    404: "Not found",
    409: "Conflict",
    410: "Gone (a 3D view of a replica that stopped)",
    413: "Too large",
    422: "Invalid request",
    429: "Rate limited",
    503: "Time limit or not ready",
}


def responses(*statuses: int) -> dict[int | str, dict[str, Any]]:
    """OpenAPI `responses=` for the given error statuses, all with the ErrorBody schema."""
    return {s: {"model": ErrorBody, "description": _DESCRIPTIONS[s]} for s in statuses}


def _validation_text(exc: RequestValidationError) -> tuple[str, list[dict[str, Any]]]:
    errors = []
    for e in exc.errors():
        loc = ".".join(str(p) for p in e.get("loc", ()) if p != "body")
        errors.append({"field": loc, "type": e.get("type", ""), "message": e.get("msg", "")})
    text = "; ".join(f"{x['field']}: {x['message']}" if x["field"] else x["message"] for x in errors[:5])
    return text, errors


def install(app: FastAPI) -> None:
    @app.exception_handler(ApiError)
    async def _api_error(request: Request, exc: ApiError) -> JSONResponse:
        return error_response(exc)

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        text, errors = _validation_text(exc)
        err = ApiError("VALIDATION", detail=text)
        body = err.body()
        body["error"]["details"] = {"errors": errors}
        return ErrorResponse(body, status_code=422)

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        code = {401: "NOT_AUTHENTICATED", 403: "FORBIDDEN", 404: "NOT_FOUND", 405: "METHOD_NOT_ALLOWED"}.get(
            exc.status_code, "VALIDATION"
        )
        if code == "VALIDATION":
            err = ApiError(code, detail=str(exc.detail))
            return ErrorResponse(err.body(), status_code=exc.status_code)
        return error_response(ApiError(code))

    # The database's own limits, the one place they become 4xx (the schemas keep most of them from arriving):
    # a number beyond its integer range (SQLite: OverflowError; PostgreSQL: DataError), text it cannot hold
    # (PostgreSQL: NUL), and a unique constraint that a concurrent request hit first.
    @app.exception_handler(DataError)
    @app.exception_handler(OverflowError)
    async def _out_of_range(request: Request, exc: Exception) -> JSONResponse:
        log.info(
            "value out of the database's range",
            extra={"request_id": getattr(request.state, "request_id", "-")},
        )
        return error_response(ApiError("OUT_OF_RANGE"))

    @app.exception_handler(IntegrityError)
    @app.exception_handler(Duplicate)
    async def _conflict(request: Request, exc: Exception) -> JSONResponse:
        return error_response(ApiError("CONFLICT"))

    @app.exception_handler(Exception)
    async def _internal(request: Request, exc: Exception) -> JSONResponse:
        request_id = getattr(request.state, "request_id", "-")
        log.error("unhandled error", exc_info=exc, extra={"request_id": request_id})
        return error_response(ApiError("INTERNAL", request_id=request_id))
