"""The LTI 1.3 launch: OIDC third-party login initiation, the id_token's checks, and what a launch makes here
(user, course membership, resource link), ending in a one-time ticket the framed page exchanges for its token.

Why a ticket and no cookie: the page runs in the platform's iframe, on another site; browsers drop third-party
cookies there (and may refuse it storage). The launch answers with a redirect to /lti/open#ticket=…; the page's
script exchanges the ticket (valid 2 minutes, once) for an API token, which the exercise page gets in its URL
fragment (#token=…, never sent to a server) and sends as a bearer token.
"""

from __future__ import annotations

import hashlib
import logging
import secrets
import time
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any
from urllib.parse import urlencode, urlsplit

import httpx
import jwt
from jwt.algorithms import RSAAlgorithm
from sqlalchemy import delete, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from server import repository as repo
from server.lti import registration
from server.models import (
    Assignment,
    LtiContext,
    LtiDeployment,
    LtiLaunch,
    LtiLoginState,
    LtiNonce,
    LtiPlatform,
    LtiResourceLink,
    LtiUser,
    User,
)

log = logging.getLogger("paltrainer.lti")

LTI = "https://purl.imsglobal.org/spec/lti/claim/"
CLAIM_MESSAGE_TYPE = LTI + "message_type"
CLAIM_VERSION = LTI + "version"
CLAIM_DEPLOYMENT = LTI + "deployment_id"
CLAIM_TARGET = LTI + "target_link_uri"
CLAIM_RESOURCE_LINK = LTI + "resource_link"
CLAIM_ROLES = LTI + "roles"
CLAIM_CONTEXT = LTI + "context"
CLAIM_CUSTOM = LTI + "custom"
CLAIM_AGS = "https://purl.imsglobal.org/spec/lti-ags/claim/endpoint"
CLAIM_NRPS = "https://purl.imsglobal.org/spec/lti-nrps/claim/namesroleservice"
CLAIM_DL_SETTINGS = "https://purl.imsglobal.org/spec/lti-dl/claim/deep_linking_settings"
RESOURCE_LINK_REQUEST = "LtiResourceLinkRequest"
DEEP_LINKING_REQUEST = "LtiDeepLinkingRequest"

STATE_SECONDS = 600  # from /lti/login to /lti/launch: the platform's login page may come in between
TICKET_SECONDS = 120
LEEWAY_SECONDS = 60  # clock skew between the platform and us
NONCE_KEEP_SECONDS = 24 * 3600  # a used nonce is remembered at least this long (beyond any token's exp)
MAX_LOGIN_STATES = (
    20_000  # logins under way at once, all platforms (a 2,000-trainee evening uses a few hundred)
)
NO_PASSWORD = "!lti"  # the password hash of accounts a launch makes: no password ever matches it

# roles (LTI 1.3 core, appendix A.2): context roles and the institution/system administrator roles
_LIS = "http://purl.imsglobal.org/vocab/lis/v2/"
_INSTRUCTOR_ROLES = {
    _LIS + "membership#Instructor",
    _LIS + "membership/Instructor#TeachingAssistant",
    "Instructor",
}
_ADMIN_ROLES = {
    _LIS + "institution/person#Administrator",
    _LIS + "system/person#Administrator",
    _LIS + "membership#Administrator",
    "Administrator",
}


class LtiRefusal(Exception):
    """A launch we refuse: a stable code, a German and an English message (shown on the error page)."""

    def __init__(self, code: str, message: str, message_en: str, status: int = 400) -> None:
        super().__init__(f"{code}: {message_en}")
        self.code, self.message, self.message_en, self.status = code, message, message_en, status


def _now() -> datetime:
    return datetime.now(UTC)


def _aware(t: datetime) -> datetime:
    return t if t.tzinfo is not None else t.replace(tzinfo=UTC)  # SQLite gives naive times back


def _hash(ticket: str) -> str:
    return hashlib.sha256(ticket.encode("utf-8")).hexdigest()


# --- the platform's keys -----------------------------------------------------------------------------


class JwksCache:
    """The platforms' public keys by JWKS URL, kept `ttl` seconds; a kid we do not know yet makes one fresh
    fetch (the platform rotated), at most once every `min_refetch` seconds per URL."""

    def __init__(
        self, transport: httpx.BaseTransport | None = None, ttl: float = 300.0, min_refetch: float = 10.0
    ) -> None:
        self.transport, self.ttl, self.min_refetch = transport, ttl, min_refetch
        self._keys: dict[str, tuple[float, dict[str, Any]]] = {}

    def _fetch(self, url: str) -> dict[str, Any]:
        with httpx.Client(transport=self.transport, timeout=10.0, follow_redirects=False) as client:
            resp = client.get(url)
            resp.raise_for_status()
            data = resp.json()
        keys = {
            k["kid"]: k for k in data.get("keys", []) if isinstance(k, dict) and isinstance(k.get("kid"), str)
        }
        self._keys[url] = (time.monotonic(), keys)
        return keys

    def key(self, url: str, kid: str) -> dict[str, Any] | None:
        """The JWK with this kid, or None (also when the platform's JWKS cannot be fetched)."""
        try:
            fetched, keys = self._keys.get(url, (0.0, {}))
            age = time.monotonic() - fetched
            if not fetched or age > self.ttl or (kid not in keys and age > self.min_refetch):
                keys = self._fetch(url)
        except (httpx.HTTPError, ValueError, AttributeError) as exc:
            log.warning("lti: platform JWKS not readable", extra={"job": f"{url}: {str(exc)[:200]}"})
            return None
        return keys.get(kid)


# --- OIDC login initiation ---------------------------------------------------------------------------


def begin_login(db: Session, params: dict[str, str], own_origin: str) -> str:
    """The URL of the platform's authorization endpoint (the REGISTERED one) with a new state and nonce.
    `own_origin`: this tool's origin (scheme://host[:port]); the launch must come back to it."""
    issuer, login_hint, target = params.get("iss"), params.get("login_hint"), params.get("target_link_uri")
    if not issuer or not login_hint or not target:
        raise LtiRefusal(
            "LTI_LOGIN_INCOMPLETE",
            "Der Anmeldeanfrage der Plattform fehlen Angaben (iss, login_hint, target_link_uri).",
            "The platform's login request lacks iss, login_hint or target_link_uri.",
        )
    try:
        target_path = urlsplit(target).path
    except ValueError:
        target_path = ""
    own = registration.origin_of(own_origin)
    if target_path != "/lti/launch" or own is None or registration.origin_of(target) != own:
        # the id_token goes to redirect_uri: only ever our own launch endpoint, never one on another host
        raise LtiRefusal(
            "LTI_BAD_TARGET",
            "Die Zieladresse des Starts (target_link_uri) ist nicht /lti/launch von PAL Trainer.",
            "The launch's target_link_uri is not PAL Trainer's /lti/launch.",
        )
    candidates = registration.platforms_of_issuer(db, issuer)
    client_id = params.get("client_id")
    if client_id:
        candidates = [p for p in candidates if p.client_id == client_id]
    if not candidates:
        raise _unregistered(issuer)
    if len(candidates) > 1:
        raise LtiRefusal(
            "LTI_CLIENT_ID_REQUIRED",
            "Für diese Plattform sind mehrere Client-IDs registriert; "
            "die Anmeldeanfrage muss client_id enthalten.",
            "Several client ids are registered for this platform; the login request must name one.",
        )
    platform = candidates[0]
    state, nonce = secrets.token_urlsafe(32), secrets.token_urlsafe(32)
    db.add(
        LtiLoginState(
            state=state,
            nonce=nonce,
            platform_id=platform.id,
            expires_at=_now() + timedelta(seconds=STATE_SECONDS),
        )
    )
    _prune_login_states(db)
    db.commit()
    query = {
        "scope": "openid",
        "response_type": "id_token",
        "response_mode": "form_post",
        "prompt": "none",
        "client_id": platform.client_id,
        "redirect_uri": target,
        "login_hint": login_hint,
        "state": state,
        "nonce": nonce,
    }
    if params.get("lti_message_hint"):
        query["lti_message_hint"] = params["lti_message_hint"]
    sep = "&" if "?" in platform.auth_login_url else "?"
    return platform.auth_login_url + sep + urlencode(query)


def _prune_login_states(db: Session) -> None:
    """Expired login states go; beyond MAX_LOGIN_STATES the oldest go too. Anyone may start a login (the
    route limits each address), so the table is bounded: under a flood of logins from many addresses a state
    lives shorter, but a real login, which comes back within seconds, still finds its own."""
    db.execute(delete(LtiLoginState).where(LtiLoginState.expires_at < _now()))
    oldest_kept = db.scalars(
        select(LtiLoginState.id).order_by(LtiLoginState.id.desc()).offset(MAX_LOGIN_STATES - 1).limit(1)
    ).first()
    if oldest_kept is not None:
        db.execute(delete(LtiLoginState).where(LtiLoginState.id < oldest_kept))


def _unregistered(issuer: str) -> LtiRefusal:
    return LtiRefusal(
        "LTI_UNKNOWN_ISSUER",
        f"Die Plattform »{issuer[:200]}« ist hier nicht registriert.",
        f"The platform '{issuer[:200]}' is not registered here.",
        403,
    )


# --- the id_token ------------------------------------------------------------------------------------


@dataclass
class Verified:
    platform: LtiPlatform
    claims: dict[str, Any]


def verify(db: Session, cache: JwksCache, id_token: str | None, state: str | None) -> Verified:
    """Check the authentication response; LtiRefusal with the reason on anything wrong."""
    if not state:
        raise LtiRefusal(
            "LTI_BAD_STATE",
            "Der Start enthält keinen Zustand (state); bitte erneut aus der Lernplattform öffnen.",
            "The launch carries no state; open it again from the platform.",
        )
    login = db.scalars(select(LtiLoginState).where(LtiLoginState.state == state)).first()
    if login is None or _aware(login.expires_at) < _now():
        raise LtiRefusal(
            "LTI_BAD_STATE",
            "Der Start ist unbekannt oder abgelaufen (state); bitte erneut aus der Lernplattform öffnen.",
            "Unknown or expired launch state; open it again from the platform.",
        )
    platform_id, expected_nonce = login.platform_id, login.nonce
    db.delete(login)  # a state is good for one launch
    db.commit()
    if not id_token:
        raise LtiRefusal(
            "LTI_BAD_TOKEN", "Der Start enthält kein id_token.", "The launch carries no id_token."
        )
    try:
        header = jwt.get_unverified_header(id_token)
        unverified = jwt.decode(id_token, options={"verify_signature": False})
    except jwt.PyJWTError as exc:
        raise LtiRefusal(
            "LTI_BAD_TOKEN", "Das id_token ist kein gültiges JWT.", "The id_token is not a valid JWT."
        ) from exc
    issuer = unverified.get("iss")
    platform = db.get(LtiPlatform, platform_id)
    if not isinstance(issuer, str) or platform is None or not registration.platforms_of_issuer(db, issuer):
        raise _unregistered(str(issuer))
    if platform.issuer != issuer:
        raise LtiRefusal(
            "LTI_BAD_STATE",
            "Der Start gehört zu einer anderen Plattform (state).",
            "The launch state belongs to another platform.",
        )
    aud = unverified.get("aud")
    audiences = [aud] if isinstance(aud, str) else aud if isinstance(aud, list) else []
    if platform.client_id not in audiences or (
        len(audiences) > 1 and unverified.get("azp") != platform.client_id
    ):
        raise LtiRefusal(
            "LTI_WRONG_AUDIENCE",
            "Das id_token ist nicht für PAL Trainer ausgestellt (aud).",
            "The id_token is not issued for PAL Trainer (aud).",
            403,
        )
    if header.get("alg") != "RS256" or not isinstance(header.get("kid"), str):
        raise LtiRefusal(
            "LTI_BAD_TOKEN",
            "Das id_token muss mit RS256 und einer Schlüssel-ID signiert sein.",
            "The id_token must be signed with RS256 and carry a key id.",
        )
    jwk = cache.key(platform.jwks_url, header["kid"])
    if jwk is None:
        raise LtiRefusal(
            "LTI_UNKNOWN_KEY",
            "Das id_token ist mit einem Schlüssel signiert, den die Plattform nicht veröffentlicht.",
            "The id_token is signed with a key the platform does not publish.",
            403,
        )
    try:
        claims: dict[str, Any] = jwt.decode(
            id_token,
            RSAAlgorithm.from_jwk(jwk),  # type: ignore[arg-type]
            algorithms=["RS256"],
            audience=platform.client_id,
            issuer=platform.issuer,
            leeway=LEEWAY_SECONDS,
            options={"require": ["exp", "iat", "nonce", "sub"]},
        )
    except jwt.ExpiredSignatureError as exc:
        raise LtiRefusal(
            "LTI_EXPIRED",
            "Das id_token ist abgelaufen; bitte erneut aus der Lernplattform öffnen.",
            "The id_token has expired; open it again from the platform.",
            403,
        ) from exc
    except jwt.InvalidSignatureError as exc:
        raise LtiRefusal(
            "LTI_BAD_SIGNATURE",
            "Die Signatur des id_token stimmt nicht.",
            "The id_token's signature is wrong.",
            403,
        ) from exc
    except jwt.PyJWTError as exc:
        raise LtiRefusal(
            "LTI_BAD_TOKEN", f"Das id_token ist ungültig: {exc}", f"The id_token is invalid: {exc}", 403
        ) from exc
    nonce = str(claims["nonce"])
    db.execute(delete(LtiNonce).where(LtiNonce.expires_at < _now()))
    if db.scalars(
        select(LtiNonce).where(LtiNonce.platform_id == platform.id, LtiNonce.nonce == nonce)
    ).first():
        raise LtiRefusal(
            "LTI_REPLAY",
            "Dieses id_token wurde schon verwendet (nonce); bitte erneut aus der Lernplattform öffnen.",
            "This id_token was used before (nonce).",
            403,
        )
    if not secrets.compare_digest(nonce.encode("utf-8"), expected_nonce.encode("utf-8")):
        raise LtiRefusal(
            "LTI_BAD_NONCE",
            "Das id_token gehört nicht zu diesem Start (nonce).",
            "The id_token does not belong to this launch (nonce).",
            403,
        )
    keep = max(float(claims["exp"]) - time.time() + LEEWAY_SECONDS, NONCE_KEEP_SECONDS)
    db.add(LtiNonce(platform_id=platform.id, nonce=nonce, expires_at=_now() + timedelta(seconds=keep)))
    try:
        db.commit()
    except IntegrityError as exc:  # the same token at the same moment twice
        db.rollback()
        raise LtiRefusal(
            "LTI_REPLAY",
            "Dieses id_token wurde schon verwendet (nonce).",
            "This id_token was used before (nonce).",
            403,
        ) from exc
    if claims.get(CLAIM_VERSION) != "1.3.0":
        raise LtiRefusal("LTI_BAD_VERSION", "Nur LTI 1.3 wird unterstützt.", "Only LTI 1.3 is supported.")
    message_type = claims.get(CLAIM_MESSAGE_TYPE)
    if message_type not in (RESOURCE_LINK_REQUEST, DEEP_LINKING_REQUEST):
        raise LtiRefusal(
            "LTI_UNSUPPORTED_MESSAGE",
            f"Die Nachricht »{str(message_type)[:80]}« wird nicht unterstützt.",
            f"The message type '{str(message_type)[:80]}' is not supported.",
        )
    deployment = claims.get(CLAIM_DEPLOYMENT)
    if (
        not isinstance(deployment, str)
        or not db.scalars(
            select(LtiDeployment).where(
                LtiDeployment.platform_id == platform.id, LtiDeployment.deployment_id == deployment
            )
        ).first()
    ):
        raise LtiRefusal(
            "LTI_UNKNOWN_DEPLOYMENT",
            f"Die Deployment-ID »{str(deployment)[:80]}« ist für diese Plattform nicht registriert.",
            f"The deployment id '{str(deployment)[:80]}' is not registered for this platform.",
            403,
        )
    return Verified(platform, claims)


# --- what a launch makes here ------------------------------------------------------------------------


def role_of(claims: dict[str, Any]) -> str:
    """ "administrator", "instructor" or "learner" from the roles claim; anything unknown is a learner."""
    roles = claims.get(CLAIM_ROLES)
    roles = {r for r in roles if isinstance(r, str)} if isinstance(roles, list) else set()
    if roles & _ADMIN_ROLES:
        return "administrator"
    return "instructor" if roles & _INSTRUCTOR_ROLES else "learner"


def _identity(db: Session, platform: LtiPlatform, sub: str) -> LtiUser | None:
    return db.scalars(select(LtiUser).where(LtiUser.platform_id == platform.id, LtiUser.sub == sub)).first()


def _new_identity(db: Session, platform: LtiPlatform, sub: str, role: str) -> LtiUser:
    """A new account for the platform's user `sub`, linked to them in one transaction. The link (platform, sub) is
    the only way from a platform user to an account: an existing account that merely has the generated name
    (someone made it before the first launch: the name is predictable) is never adopted; the new account gets a
    fresh name then."""
    base = f"lti{platform.id}-{hashlib.sha256(sub.encode('utf-8')).hexdigest()[:16]}"
    for attempt in range(5):
        username = base if attempt == 0 else f"{base}-{secrets.token_hex(4)}"
        if repo.user_by_name(db, username) is not None:
            continue
        try:
            user = User(username=username, password_hash=NO_PASSWORD, role=role)
            db.add(user)
            db.flush()
            link = LtiUser(platform_id=platform.id, sub=sub, user_id=user.id)
            db.add(link)
            db.commit()
            return link
        except IntegrityError:
            db.rollback()
            made = _identity(db, platform, sub)  # the same person's other launch at the same moment made it
            if made is not None:
                return made
    raise LtiRefusal(
        "LTI_USER_FAILED",
        "Das Konto für den Start ließ sich nicht anlegen; bitte erneut öffnen.",
        "The account for this launch could not be made; please open it again.",
        503,
    )


def platform_user(
    db: Session, platform: LtiPlatform, claims: dict[str, Any], teaches: bool
) -> tuple[User, LtiUser]:
    """The account of the platform's user (claims "sub", name, email), made on their first launch or roster pull;
    a user the platform says teaches becomes an instructor here."""
    sub = str(claims["sub"])[:255]
    name = str(
        claims.get("name") or " ".join(str(claims.get(k, "")) for k in ("given_name", "family_name"))
    ).strip()
    email = claims.get("email") if isinstance(claims.get("email"), str) else ""
    link = _identity(db, platform, sub)
    if link is None:
        # the user name is ours, not the platform's: names may repeat or change there, (platform, sub) does not
        link = _new_identity(db, platform, sub, "instructor" if teaches else "student")
    found = repo.user_by_id(db, link.user_id)
    assert found is not None
    user = found
    if teaches and user.role == "student":  # the platform says they teach (signed): they may manage courses
        user.role = "instructor"
    link.name, link.email = name[:200], str(email)[:320]
    db.commit()
    return user, link


def _service_url(platform: LtiPlatform, value: Any, what: str) -> str | None:
    """A service URL from the id_token, kept only if it is on the platform's registered origins (and fits)."""
    if not isinstance(value, str):
        return None
    if len(value) <= 1000 and registration.service_url_ok(platform, value):
        return value
    log.warning(
        "lti: service URL not on the platform's origins, ignored",
        extra={"job": f"platform {platform.id} {what}: {value[:200]}"},
    )
    return None


def _context(
    db: Session, platform: LtiPlatform, claims: dict[str, Any], user: User, teaches: bool
) -> LtiContext | None:
    ctx = claims.get(CLAIM_CONTEXT)
    if not isinstance(ctx, dict) or not isinstance(ctx.get("id"), str):
        return None
    row = db.scalars(
        select(LtiContext).where(
            LtiContext.platform_id == platform.id, LtiContext.context_id == ctx["id"][:255]
        )
    ).first()
    title = str(ctx.get("title") or ctx.get("label") or "LTI-Kurs")[:200]
    if row is None:
        row = LtiContext(platform_id=platform.id, context_id=ctx["id"][:255], title=title)
        db.add(row)
    nrps = claims.get(CLAIM_NRPS)
    if isinstance(nrps, dict) and "context_memberships_url" in nrps:
        row.memberships_url = _service_url(
            platform, nrps["context_memberships_url"], "context_memberships_url"
        )
    row.title = title
    if row.course_id is None or repo.course_by_id(db, row.course_id) is None:
        row.course_id = None
        if teaches:  # a course is made by its first instructor's launch; learners before that wait for it
            row.course_id = repo.create_course(db, title, repo.new_join_code(), [user.id]).id
    db.commit()
    if row.course_id is not None:
        repo.add_member(db, row.course_id, user.id, "instructor" if teaches else "student")
    return row


def _resource_link(
    db: Session, platform: LtiPlatform, claims: dict[str, Any], context: LtiContext | None
) -> LtiResourceLink | None:
    rl = claims.get(CLAIM_RESOURCE_LINK)
    if not isinstance(rl, dict) or not isinstance(rl.get("id"), str):
        return None
    row = db.scalars(
        select(LtiResourceLink).where(
            LtiResourceLink.platform_id == platform.id, LtiResourceLink.resource_link_id == rl["id"][:255]
        )
    ).first()
    if row is None:
        row = LtiResourceLink(platform_id=platform.id, resource_link_id=rl["id"][:255], ags_scopes=[])
        db.add(row)
    row.title = str(rl.get("title") or "")[:500]
    row.context_pk = context.id if context is not None else None
    given = claims.get(CLAIM_CUSTOM)
    custom: dict[str, Any] = given if isinstance(given, dict) else {}
    slug = custom.get("exercise")
    row.exercise_slug = slug if isinstance(slug, str) and repo.exercise_by_slug(db, slug) else None
    assignment_id = str(custom.get("assignment", ""))
    assignment = (
        db.get(Assignment, int(assignment_id))
        if assignment_id.isdigit() and len(assignment_id) < 10
        else None
    )
    # an assignment must belong to the platform course's course: a link cannot reach another class's exam
    ok = assignment is not None and context is not None and assignment.course_id == context.course_id
    row.assignment_id = assignment.id if ok and assignment is not None else None
    ags = claims.get(CLAIM_AGS)
    if isinstance(ags, dict):
        row.lineitem_url = _service_url(platform, ags.get("lineitem"), "lineitem")
        row.lineitems_url = _service_url(platform, ags.get("lineitems"), "lineitems")
        row.ags_scopes = [s for s in ags.get("scope", []) if isinstance(s, str)]
    db.commit()
    return row


def landing_slug(db: Session, link: LtiResourceLink | None) -> str | None:
    """The exercise the launch opens: the link's, else its assignment's first."""
    if link is None:
        return None
    if link.exercise_slug:
        return link.exercise_slug
    if link.assignment_id is not None:
        assignment = db.get(Assignment, link.assignment_id)
        if assignment is not None and assignment.exercises:
            return str(assignment.exercises[0])
    return None


def accept(db: Session, verified: Verified) -> tuple[LtiLaunch, str]:
    """Users, course, link from a verified launch; the launch row and its one-time ticket."""
    platform, claims = verified.platform, verified.claims
    role = role_of(claims)
    teaches = role in ("instructor", "administrator")
    user, lti_user = platform_user(db, platform, claims, teaches)
    context = _context(db, platform, claims, user, teaches)
    message_type = str(claims[CLAIM_MESSAGE_TYPE])
    link = _resource_link(db, platform, claims, context) if message_type == RESOURCE_LINK_REQUEST else None
    ticket = secrets.token_urlsafe(32)
    launch = LtiLaunch(
        platform_id=platform.id,
        deployment_id=str(claims[CLAIM_DEPLOYMENT]),
        message_type=message_type,
        user_id=user.id,
        lti_user_pk=lti_user.id,
        resource_link_pk=link.id if link else None,
        exercise_slug=landing_slug(db, link),
        role=role,
        ticket_hash=_hash(ticket),
        ticket_expires_at=_now() + timedelta(seconds=TICKET_SECONDS),
    )
    if message_type == DEEP_LINKING_REQUEST:
        settings = claims.get(CLAIM_DL_SETTINGS)
        if not isinstance(settings, dict) or not isinstance(settings.get("deep_link_return_url"), str):
            raise LtiRefusal(
                "LTI_BAD_DEEP_LINKING",
                "Der Deep-Linking-Anfrage fehlt die Rücksprungadresse.",
                "The deep linking request lacks its return URL.",
            )
        if not teaches:
            raise LtiRefusal(
                "LTI_NOT_INSTRUCTOR",
                "Aufgaben auswählen dürfen nur Lehrkräfte.",
                "Only instructors may pick exercises.",
                403,
            )
        launch.deep_link_return_url = settings["deep_link_return_url"][:1000]
        data = settings.get("data")
        launch.deep_link_data = data if isinstance(data, str) else None
    db.add(launch)
    db.commit()
    log.info("lti launch", extra={"job": f"{message_type} platform {platform.id} user {user.id} role {role}"})
    return launch, ticket


def redeem(db: Session, ticket: str) -> LtiLaunch | None:
    """The launch of a ticket that is valid and unused (it is used up now), else None."""
    launch = db.scalars(select(LtiLaunch).where(LtiLaunch.ticket_hash == _hash(ticket))).first()
    if launch is None or launch.ticket_used_at is not None or _aware(launch.ticket_expires_at) < _now():
        return None
    launch.ticket_used_at = _now()
    db.commit()
    return launch


def resource_link_for(db: Session, user_id: int, exercise_slug: str) -> LtiResourceLink | None:
    """The resource link of the user's latest launch into this exercise (for the grade passback), or None."""
    launch = db.scalars(
        select(LtiLaunch)
        .where(
            LtiLaunch.user_id == user_id,
            LtiLaunch.exercise_slug == exercise_slug,
            LtiLaunch.resource_link_pk.is_not(None),
        )
        .order_by(LtiLaunch.created_at.desc(), LtiLaunch.id.desc())
        .limit(1)
    ).first()
    return db.get(LtiResourceLink, launch.resource_link_pk) if launch and launch.resource_link_pk else None
