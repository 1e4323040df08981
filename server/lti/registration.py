"""Registered platforms: by the admin (CLI `paltrainer admin lti-register`, POST /api/v1/admin/lti/platforms)
or by LTI Dynamic Registration (/lti/register: the platform's OpenID configuration and a registration token;
we send our tool configuration to the platform and store what it answers)."""

from __future__ import annotations

import logging
from typing import Any
from urllib.parse import urlsplit

import httpx
from sqlalchemy import select
from sqlalchemy.orm import Session

from server.models import LtiDeployment, LtiPlatform

log = logging.getLogger("paltrainer.lti")

CLAIM_PLATFORM_CONFIG = "https://purl.imsglobal.org/spec/lti-platform-configuration"
CLAIM_TOOL_CONFIG = "https://purl.imsglobal.org/spec/lti-tool-configuration"
TOOL_SCOPES = ("https://purl.imsglobal.org/spec/lti-ags/scope/lineitem",
               "https://purl.imsglobal.org/spec/lti-ags/scope/lineitem.readonly",
               "https://purl.imsglobal.org/spec/lti-ags/scope/result.readonly",
               "https://purl.imsglobal.org/spec/lti-ags/scope/score",
               "https://purl.imsglobal.org/spec/lti-nrps/scope/contextmembership.readonly")


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
    return parts.scheme == "https" or (parts.scheme == "http" and parts.hostname in ("127.0.0.1", "localhost", "::1"))


def origin(url: str) -> str:
    parts = urlsplit(url)
    return f"{parts.scheme}://{parts.netloc}"


def register(db: Session, *, issuer: str, client_id: str, auth_login_url: str, token_url: str, jwks_url: str,
             deployment_ids: list[str], name: str = "") -> LtiPlatform:
    """Store a platform (or update the one with this issuer and client id) and add its deployment ids."""
    platform = db.scalars(select(LtiPlatform).where(LtiPlatform.issuer == issuer,
                                                    LtiPlatform.client_id == client_id)).first()
    if platform is None:
        platform = LtiPlatform(issuer=issuer, client_id=client_id, auth_login_url=auth_login_url,
                               token_url=token_url, jwks_url=jwks_url, name=name or issuer)
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


def deployments(db: Session, platform_id: int) -> list[str]:
    return list(db.scalars(select(LtiDeployment.deployment_id).where(LtiDeployment.platform_id == platform_id)
                           .order_by(LtiDeployment.id)))


def platforms(db: Session) -> list[LtiPlatform]:
    return list(db.scalars(select(LtiPlatform).order_by(LtiPlatform.id)))


def platforms_of_issuer(db: Session, issuer: str) -> list[LtiPlatform]:
    return list(db.scalars(select(LtiPlatform).where(LtiPlatform.issuer == issuer).order_by(LtiPlatform.id)))


def platform_out(db: Session, p: LtiPlatform) -> dict[str, Any]:
    return {"id": p.id, "name": p.name, "issuer": p.issuer, "client_id": p.client_id,
            "auth_login_url": p.auth_login_url, "token_url": p.token_url, "jwks_url": p.jwks_url,
            "deployment_ids": deployments(db, p.id), "created_at": p.created_at.isoformat()}


def tool_urls(base_url: str) -> dict[str, str]:
    """The URLs a platform's admin enters (shown on /lti/config)."""
    base = base_url.rstrip("/")
    return {"tool_url": f"{base}/lti/launch", "login_url": f"{base}/lti/login", "redirect_url": f"{base}/lti/launch",
            "jwks_url": f"{base}/lti/jwks", "deep_linking_url": f"{base}/lti/launch",
            "registration_url": f"{base}/lti/register", "config_url": f"{base}/lti/config"}


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
            "messages": [{"type": "LtiDeepLinkingRequest", "target_link_uri": urls["deep_linking_url"],
                          "label": "PAL Trainer: Aufgabe einfügen"}],
        },
    }


async def dynamic_register(db: Session, openid_configuration: str, registration_token: str | None, base_url: str,
                           transport: httpx.AsyncBaseTransport | None = None) -> LtiPlatform:
    """Fetch the platform's configuration, send ours to its registration endpoint, store the platform."""
    if not url_ok(openid_configuration):
        raise RegistrationError("Die Adresse der Plattform-Konfiguration ist ungültig (https erforderlich).",
                                "The platform configuration URL is invalid (https required).")
    async with httpx.AsyncClient(transport=transport, timeout=10.0, follow_redirects=False) as client:
        try:
            resp = await client.get(openid_configuration)
            resp.raise_for_status()
            config = resp.json()
        except (httpx.HTTPError, ValueError) as exc:
            log.warning("lti dynamic registration: configuration not readable", extra={"job": str(exc)[:200]})
            raise RegistrationError("Die Konfiguration der Plattform ließ sich nicht laden.",
                                    "The platform configuration could not be loaded.") from exc
        needed = ("issuer", "authorization_endpoint", "token_endpoint", "jwks_uri", "registration_endpoint")
        if not isinstance(config, dict) or not all(isinstance(config.get(k), str) for k in needed):
            raise RegistrationError("Der Konfiguration der Plattform fehlen Angaben.",
                                    "The platform configuration lacks fields.")
        # the configuration must come from the issuer it names (spec: same origin), and every URL be usable
        if origin(config["issuer"]) != origin(openid_configuration) or not all(url_ok(config[k]) for k in needed):
            raise RegistrationError("Die Konfiguration der Plattform passt nicht zu ihrer Adresse.",
                                    "The platform configuration does not match its address.")
        headers = {"Authorization": f"Bearer {registration_token}"} if registration_token else {}
        try:
            answer = await client.post(config["registration_endpoint"], json=tool_registration(base_url),
                                       headers=headers)
            answer.raise_for_status()
            registered = answer.json()
        except (httpx.HTTPError, ValueError) as exc:
            log.warning("lti dynamic registration refused by the platform", extra={"job": str(exc)[:200]})
            raise RegistrationError("Die Plattform hat die Registrierung abgelehnt.",
                                    "The platform refused the registration.") from exc
    client_id = registered.get("client_id") if isinstance(registered, dict) else None
    if not isinstance(client_id, str) or not client_id:
        raise RegistrationError("Die Plattform hat keine Client-ID zurückgegeben.",
                                "The platform returned no client id.")
    tool_config = registered.get(CLAIM_TOOL_CONFIG) or {}
    deployment = tool_config.get("deployment_id") if isinstance(tool_config, dict) else None
    platform_config = config.get(CLAIM_PLATFORM_CONFIG) or {}
    name = platform_config.get("product_family_code", "") if isinstance(platform_config, dict) else ""
    return register(db, issuer=config["issuer"], client_id=client_id,
                    auth_login_url=config["authorization_endpoint"], token_url=config["token_endpoint"],
                    jwks_url=config["jwks_uri"], deployment_ids=[deployment] if isinstance(deployment, str) else [],
                    name=str(name)[:200])
