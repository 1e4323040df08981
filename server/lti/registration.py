"""Registered platforms: by the admin (CLI `paltrainer admin lti-register`, POST /api/v1/admin/lti/platforms)
or by LTI Dynamic Registration (/lti/register with a single-use code from our admin: the platform's OpenID
configuration and a registration token; we send our tool configuration to the platform and store what it
answers). A platform's registered origins are also the only places its service URLs may point to."""

from __future__ import annotations

import logging
import secrets
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any
from urllib.parse import urlsplit

import httpx
import jwt
from sqlalchemy import delete, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from server.models import LtiDeployment, LtiPlatform, LtiRegistrationCode

log = logging.getLogger("paltrainer.lti")

CLAIM_PLATFORM_CONFIG = "https://purl.imsglobal.org/spec/lti-platform-configuration"
CLAIM_TOOL_CONFIG = "https://purl.imsglobal.org/spec/lti-tool-configuration"
TOOL_SCOPES = (
    "https://purl.imsglobal.org/spec/lti-ags/scope/lineitem",
    "https://purl.imsglobal.org/spec/lti-ags/scope/lineitem.readonly",
    "https://purl.imsglobal.org/spec/lti-ags/scope/result.readonly",
    "https://purl.imsglobal.org/spec/lti-ags/scope/score",
    "https://purl.imsglobal.org/spec/lti-nrps/scope/contextmembership.readonly",
)


class RegistrationError(Exception):
    """Dynamic registration failed: `message` (German) and `message_en` say why."""

    def __init__(self, message: str, message_en: str) -> None:
        super().__init__(message_en)
        self.message, self.message_en = message, message_en


def url_ok(url: str) -> bool:
    """An https URL (http only for this machine, as in tests and local trials)."""
    try:
        parts = urlsplit(url)
    except ValueError:
        return False
    if not parts.netloc or any(c.isspace() for c in url):
        return False
    return parts.scheme == "https" or (
        parts.scheme == "http" and parts.hostname in ("127.0.0.1", "localhost", "::1")
    )


def origin(url: str) -> str:
    parts = urlsplit(url)
    return f"{parts.scheme}://{parts.netloc}"


_DEFAULT_PORTS = {"http": 80, "https": 443}
_LOOPBACK = ("127.0.0.1", "localhost", "::1")
Origin = tuple[str, str, int]  # scheme, host, port


def origin_of(url: str) -> Origin | None:
    """The origin an http(s) URL is requested at, parsed as httpx parses it (the client that requests it); None
    for anything else, and for URLs with user info or a backslash (read differently by different parsers)."""
    if any(c.isspace() or c == "\\" for c in url):
        return None
    try:
        parsed = httpx.URL(url)
    except (httpx.InvalidURL, TypeError, ValueError):
        return None
    if parsed.scheme not in _DEFAULT_PORTS or not parsed.host or parsed.userinfo:
        return None
    return parsed.scheme, parsed.host, parsed.port or _DEFAULT_PORTS[parsed.scheme]


def platform_origins(platform: LtiPlatform) -> set[Origin]:
    """The origins of the platform's issuer and its registered login, token and key set URLs: https ones, and
    http ones on this machine (a platform registered on loopback, as in local trials and the tests)."""
    found = {
        origin_of(u)
        for u in (platform.issuer, platform.auth_login_url, platform.token_url, platform.jwks_url)
    }
    return {o for o in found if o is not None and (o[0] == "https" or o[1] in _LOOPBACK)}


def service_url_ok(platform: LtiPlatform, url: str) -> bool:
    """Whether we may request `url` as one of the platform's services (AGS line items and scores, NRPS roster):
    only on the platform's registered origins. The URLs come from its id_token or its answers; anything else
    would let whoever controls them make us request our own network (SSRF)."""
    found = origin_of(url)
    return found is not None and found in platform_origins(platform)


# what a platform registered by hand may hold (the columns of LtiPlatform and LtiDeployment)
PLATFORM_LIMITS = {
    "issuer": 500,
    "client_id": 255,
    "auth_login_url": 1000,
    "token_url": 1000,
    "jwks_url": 1000,
    "name": 200,
}
DEPLOYMENT_MAX, DEPLOYMENTS_MAX = 255, 50
PLATFORM_URLS = ("issuer", "auth_login_url", "token_url", "jwks_url")
Problem = tuple[str, str]  # German, English


def platform_problems(
    *,
    issuer: str,
    client_id: str,
    auth_login_url: str,
    token_url: str,
    jwks_url: str,
    deployment_ids: list[str],
    name: str = "",
) -> dict[str, Problem]:
    """What keeps a platform from being registered by hand, per field (German, English); empty when nothing does.
    The one check of `paltrainer admin lti-register` and POST /api/v1/admin/lti/platforms: the URLs https (http
    only on this machine), every text within its column and without NUL, at most 50 deployment ids."""
    values = {
        "issuer": issuer,
        "client_id": client_id,
        "auth_login_url": auth_login_url,
        "token_url": token_url,
        "jwks_url": jwks_url,
        "name": name,
    }
    found: dict[str, Problem] = {}
    for field, value in values.items():
        limit = PLATFORM_LIMITS[field]
        if "\x00" in value:
            found[field] = ("enthält das Zeichen NUL", "contains the NUL character")
        elif len(value) > limit:
            found[field] = (f"höchstens {limit} Zeichen", f"at most {limit} characters")
        elif field in PLATFORM_URLS and not url_ok(value):
            found[field] = (
                "keine gültige https-Adresse (z. B. https://moodle.schule.de/…)",
                "not a valid https URL (e.g. https://moodle.school.org/…)",
            )
        elif field == "client_id" and not value.strip():
            found[field] = ("darf nicht leer sein", "must not be empty")
    if len(deployment_ids) > DEPLOYMENTS_MAX:
        found["deployment_ids"] = (
            f"höchstens {DEPLOYMENTS_MAX} Deployment-IDs",
            f"at most {DEPLOYMENTS_MAX} deployment ids",
        )
    elif any(not d.strip() or len(d) > DEPLOYMENT_MAX or "\x00" in d for d in deployment_ids):
        found["deployment_ids"] = (
            f"jede Deployment-ID 1 bis {DEPLOYMENT_MAX} Zeichen",
            f"each deployment id 1 to {DEPLOYMENT_MAX} characters",
        )
    return found


def register(
    db: Session,
    *,
    issuer: str,
    client_id: str,
    auth_login_url: str,
    token_url: str,
    jwks_url: str,
    deployment_ids: list[str],
    name: str = "",
) -> LtiPlatform:
    """Store a platform (or update the one with this issuer and client id) and add its deployment ids."""
    platform = db.scalars(
        select(LtiPlatform).where(LtiPlatform.issuer == issuer, LtiPlatform.client_id == client_id)
    ).first()
    if platform is None:
        platform = LtiPlatform(
            issuer=issuer,
            client_id=client_id,
            auth_login_url=auth_login_url,
            token_url=token_url,
            jwks_url=jwks_url,
            name=name or issuer,
        )
        db.add(platform)
        db.flush()
    else:
        platform.auth_login_url, platform.token_url, platform.jwks_url = auth_login_url, token_url, jwks_url
        if name:
            platform.name = name
    known = set(deployments(db, platform.id))
    for dep in deployment_ids:
        if dep and dep not in known:
            db.add(LtiDeployment(platform_id=platform.id, deployment_id=dep))
            known.add(dep)
    db.commit()
    log.info("lti platform registered", extra={"job": f"{issuer} client {client_id}"})
    return platform


# --- single-use registration codes ---------------------------------------------------------------------

REGISTRATION_DAYS = 7


@dataclass(frozen=True)
class RegistrationCode:
    jti: str
    expires_at: datetime


def registration_code(settings: Any, minutes: int = REGISTRATION_DAYS * 24 * 60) -> str:
    """A signed code that allows one dynamic registration (within `minutes`); its id makes it single use."""
    now = datetime.now(UTC)
    return jwt.encode(
        {
            "purpose": "lti-register",
            "jti": secrets.token_urlsafe(16),
            "iat": now,
            "exp": now + timedelta(minutes=minutes),
        },
        settings.jwt_secret(),
        algorithm="HS256",
    )


def registration_url(base: str, settings: Any) -> str:
    return f"{base}/lti/register?code={registration_code(settings)}"


def read_code(db: Session, settings: Any, code: str | None) -> RegistrationCode | None:
    """The code if we signed it, it has not expired and was not used yet; else None."""
    if not code:
        return None
    try:
        claims = jwt.decode(
            code, settings.jwt_secret(), algorithms=["HS256"], options={"require": ["exp", "jti"]}
        )
    except jwt.PyJWTError:
        return None
    jti = claims.get("jti")
    if claims.get("purpose") != "lti-register" or not isinstance(jti, str) or not 0 < len(jti) <= 64:
        return None
    if db.scalars(select(LtiRegistrationCode.id).where(LtiRegistrationCode.jti == jti)).first() is not None:
        return None
    return RegistrationCode(jti, datetime.fromtimestamp(int(claims["exp"]), UTC))


def use_code(db: Session, code: RegistrationCode) -> bool:
    """Use the code up (before the platform is contacted); False if another request used it first."""
    db.execute(delete(LtiRegistrationCode).where(LtiRegistrationCode.expires_at < datetime.now(UTC)))
    db.add(LtiRegistrationCode(jti=code.jti, expires_at=code.expires_at))
    try:
        db.commit()
    except IntegrityError:
        db.rollback()
        return False
    return True


def deployments(db: Session, platform_id: int) -> list[str]:
    return list(
        db.scalars(
            select(LtiDeployment.deployment_id)
            .where(LtiDeployment.platform_id == platform_id)
            .order_by(LtiDeployment.id)
        )
    )


def platforms(db: Session) -> list[LtiPlatform]:
    return list(db.scalars(select(LtiPlatform).order_by(LtiPlatform.id)))


def platforms_of_issuer(db: Session, issuer: str) -> list[LtiPlatform]:
    return list(db.scalars(select(LtiPlatform).where(LtiPlatform.issuer == issuer).order_by(LtiPlatform.id)))


def platform_out(db: Session, p: LtiPlatform) -> dict[str, Any]:
    return {
        "id": p.id,
        "name": p.name,
        "issuer": p.issuer,
        "client_id": p.client_id,
        "auth_login_url": p.auth_login_url,
        "token_url": p.token_url,
        "jwks_url": p.jwks_url,
        "deployment_ids": deployments(db, p.id),
        "created_at": p.created_at.isoformat(),
    }


def tool_urls(base_url: str) -> dict[str, str]:
    """The URLs a platform's admin enters (shown on /lti/config)."""
    base = base_url.rstrip("/")
    return {
        "tool_url": f"{base}/lti/launch",
        "login_url": f"{base}/lti/login",
        "redirect_url": f"{base}/lti/launch",
        "jwks_url": f"{base}/lti/jwks",
        "deep_linking_url": f"{base}/lti/launch",
        "registration_url": f"{base}/lti/register",
        "config_url": f"{base}/lti/config",
    }


def tool_registration(base_url: str) -> dict[str, Any]:
    """Our client registration for Dynamic Registration (LTI Dynamic Registration 1.0, section 3.5)."""
    urls = tool_urls(base_url)
    return {
        "application_type": "web",
        "response_types": ["id_token"],
        "grant_types": ["implicit", "client_credentials"],
        "initiate_login_uri": urls["login_url"],
        "redirect_uris": [urls["redirect_url"]],
        "client_name": "PAL Trainer",
        "jwks_uri": urls["jwks_url"],
        "token_endpoint_auth_method": "private_key_jwt",
        "scope": " ".join(TOOL_SCOPES),
        CLAIM_TOOL_CONFIG: {
            "domain": urlsplit(base_url).netloc,
            "target_link_uri": urls["tool_url"],
            "description": "PAL-Prüfungsaufgaben (CNC) üben, simulieren und bewerten",
            "claims": ["iss", "sub", "name", "given_name", "family_name", "email"],
            "messages": [
                {
                    "type": "LtiDeepLinkingRequest",
                    "target_link_uri": urls["deep_linking_url"],
                    "label": "PAL Trainer: Aufgabe einfügen",
                }
            ],
        },
    }


async def dynamic_register(
    db: Session,
    openid_configuration: str,
    registration_token: str | None,
    base_url: str,
    transport: httpx.AsyncBaseTransport | None = None,
) -> LtiPlatform:
    """Fetch the platform's configuration, send ours to its registration endpoint, store the platform."""
    if not url_ok(openid_configuration):
        raise RegistrationError(
            "Die Adresse der Plattform-Konfiguration ist ungültig (https erforderlich).",
            "The platform configuration URL is invalid (https required).",
        )
    async with httpx.AsyncClient(transport=transport, timeout=10.0, follow_redirects=False) as client:
        try:
            resp = await client.get(openid_configuration)
            resp.raise_for_status()
            config = resp.json()
        except (httpx.HTTPError, ValueError) as exc:
            log.warning("lti dynamic registration: configuration not readable", extra={"job": str(exc)[:200]})
            raise RegistrationError(
                "Die Konfiguration der Plattform ließ sich nicht laden.",
                "The platform configuration could not be loaded.",
            ) from exc
        needed = ("issuer", "authorization_endpoint", "token_endpoint", "jwks_uri", "registration_endpoint")
        if not isinstance(config, dict) or not all(isinstance(config.get(k), str) for k in needed):
            raise RegistrationError(
                "Der Konfiguration der Plattform fehlen Angaben.", "The platform configuration lacks fields."
            )
        # the configuration must come from the issuer it names (spec: same origin), and every URL be usable
        if origin(config["issuer"]) != origin(openid_configuration) or not all(
            url_ok(config[k]) for k in needed
        ):
            raise RegistrationError(
                "Die Konfiguration der Plattform passt nicht zu ihrer Adresse.",
                "The platform configuration does not match its address.",
            )
        headers = {"Authorization": f"Bearer {registration_token}"} if registration_token else {}
        try:
            answer = await client.post(
                config["registration_endpoint"], json=tool_registration(base_url), headers=headers
            )
            answer.raise_for_status()
            registered = answer.json()
        except (httpx.HTTPError, ValueError) as exc:
            log.warning("lti dynamic registration refused by the platform", extra={"job": str(exc)[:200]})
            raise RegistrationError(
                "Die Plattform hat die Registrierung abgelehnt.", "The platform refused the registration."
            ) from exc
    client_id = registered.get("client_id") if isinstance(registered, dict) else None
    if not isinstance(client_id, str) or not client_id:
        raise RegistrationError(
            "Die Plattform hat keine Client-ID zurückgegeben.", "The platform returned no client id."
        )
    tool_config = registered.get(CLAIM_TOOL_CONFIG) or {}
    deployment = tool_config.get("deployment_id") if isinstance(tool_config, dict) else None
    platform_config = config.get(CLAIM_PLATFORM_CONFIG) or {}
    name = platform_config.get("product_family_code", "") if isinstance(platform_config, dict) else ""
    return register(
        db,
        issuer=config["issuer"],
        client_id=client_id,
        auth_login_url=config["authorization_endpoint"],
        token_url=config["token_endpoint"],
        jwks_url=config["jwks_uri"],
        deployment_ids=[deployment] if isinstance(deployment, str) else [],
        name=str(name)[:200],
    )
