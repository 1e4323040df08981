"""A stand-in LTI 1.3 platform for the launch and security tests: its own RSA key pair, id_tokens signed with
PyJWT, its JWKS served through an httpx MockTransport (no network), and the OIDC login → launch round trip."""

from __future__ import annotations

import json
import secrets
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, urlsplit

import httpx
import jwt
from cryptography.hazmat.primitives.asymmetric import rsa
from fastapi.testclient import TestClient
from jwt.algorithms import RSAAlgorithm

from server.lti.launch import JwksCache
from server.security import make_token

LTI = "https://purl.imsglobal.org/spec/lti/claim/"
LIS = "http://purl.imsglobal.org/vocab/lis/v2/"
INSTRUCTOR = [LIS + "membership#Instructor"]
LEARNER = [LIS + "membership#Learner"]


def rsa_key() -> tuple[rsa.RSAPrivateKey, dict[str, Any]]:
    private = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    kid = secrets.token_hex(6)
    jwk = json.loads(RSAAlgorithm.to_jwk(private.public_key()))
    jwk.update({"kid": kid, "alg": "RS256", "use": "sig"})
    return private, jwk


class Platform:
    """One platform (issuer, client id, deployment) with a published key; `requests` counts JWKS fetches."""

    def __init__(
        self,
        issuer: str = "https://lms.example.test",
        client_id: str = "pal-client",
        deployment: str = "dep-1",
    ) -> None:
        self.issuer, self.client_id, self.deployment = issuer, client_id, deployment
        self.key, self.jwk = rsa_key()
        self.jwks_fetches = 0

    @property
    def jwks_url(self) -> str:
        return f"{self.issuer}/mod/lti/certs.php"

    @property
    def auth_url(self) -> str:
        return f"{self.issuer}/mod/lti/auth.php"

    def handler(self, request: httpx.Request) -> httpx.Response:
        if str(request.url) == self.jwks_url:
            self.jwks_fetches += 1
            return httpx.Response(200, json={"keys": [self.jwk]})
        return httpx.Response(404)

    def body(self, deployment_ids: list[str] | None = None) -> dict[str, Any]:
        return {
            "issuer": self.issuer,
            "client_id": self.client_id,
            "auth_login_url": self.auth_url,
            "token_url": f"{self.issuer}/mod/lti/token.php",
            "jwks_url": self.jwks_url,
            "deployment_ids": deployment_ids or [self.deployment],
            "name": "Moodle Testschule",
        }

    def claims(
        self, nonce: str, sub: str = "user-1", roles: list[str] | None = None, **extra: Any
    ) -> dict[str, Any]:
        now = int(time.time())
        claims: dict[str, Any] = {
            "iss": self.issuer,
            "aud": self.client_id,
            "sub": sub,
            "iat": now,
            "exp": now + 300,
            "nonce": nonce,
            "name": "Erika Mustermann",
            "email": "erika@example.test",
            LTI + "message_type": "LtiResourceLinkRequest",
            LTI + "version": "1.3.0",
            LTI + "deployment_id": self.deployment,
            LTI + "target_link_uri": "http://127.0.0.1/lti/launch",
            LTI + "roles": roles if roles is not None else LEARNER,
            LTI + "context": {"id": "course-7", "label": "FK1", "title": "Fachklasse CNC 1"},
            LTI + "resource_link": {"id": "link-1", "title": "Gerade"},
            LTI + "custom": {"exercise": "pal-01-g1-gerade"},
            "https://purl.imsglobal.org/spec/lti-ags/claim/endpoint": {
                "scope": ["https://purl.imsglobal.org/spec/lti-ags/scope/score"],
                "lineitems": f"{self.issuer}/ags/7/lineitems",
                "lineitem": f"{self.issuer}/ags/7/lineitems/1/lineitem",
            },
            "https://purl.imsglobal.org/spec/lti-nrps/claim/namesroleservice": {
                "context_memberships_url": f"{self.issuer}/nrps/7/memberships",
                "service_versions": ["2.0"],
            },
        }
        claims.update(extra)
        return claims

    def sign(
        self, claims: dict[str, Any], key: rsa.RSAPrivateKey | None = None, kid: str | None = None
    ) -> str:
        return jwt.encode(claims, key or self.key, algorithm="RS256", headers={"kid": kid or self.jwk["kid"]})


def install(client: TestClient, *platforms: Platform) -> None:
    """Serve the platforms' JWKS to the app through a mock transport."""
    by_origin = {p.issuer: p for p in platforms}

    def handler(request: httpx.Request) -> httpx.Response:
        for issuer, p in by_origin.items():
            if str(request.url).startswith(issuer):
                return p.handler(request)
        return httpx.Response(404)

    transport = httpx.MockTransport(handler)
    client.app.state.lti_jwks = JwksCache(transport=transport)  # type: ignore[attr-defined]
    client.app.state.lti_transport = transport  # type: ignore[attr-defined]


def admin_headers(client: TestClient) -> dict[str, str]:
    from server import repository as repo

    app: Any = client.app
    with app.state.db.session() as db:
        user = repo.user_by_name(db, "lti-admin") or repo.create_user(db, "lti-admin", "!", "admin")
    return {"Authorization": f"Bearer {make_token(app.state.settings.jwt_secret(), user.id, 'admin', 60)}"}


def register(client: TestClient, platform: Platform, deployment_ids: list[str] | None = None) -> None:
    r = client.post(
        "/api/v1/admin/lti/platforms", json=platform.body(deployment_ids), headers=admin_headers(client)
    )
    assert r.status_code == 201, r.text


def login(client: TestClient, platform: Platform, client_id: str | None = None) -> tuple[str, str]:
    """OIDC login initiation; returns (state, nonce) from the redirect to the platform's auth URL."""
    r = client.get(
        "/lti/login",
        params={
            "iss": platform.issuer,
            "login_hint": "42",
            "target_link_uri": "http://127.0.0.1/lti/launch",
            "client_id": client_id or platform.client_id,
            "lti_message_hint": "hint-9",
        },
        follow_redirects=False,
    )
    assert r.status_code == 302, r.text
    location = r.headers["location"]
    assert location.startswith(platform.auth_url + "?")
    query = parse_qs(urlsplit(location).query)
    return query["state"][0], query["nonce"][0]


def launch(
    client: TestClient, platform: Platform, token_for: Any = None, state: str | None = None, **claims: Any
) -> httpx.Response:
    """A whole launch: login, then the form post of an id_token made by `token_for(nonce)` (default: signed
    claims with `claims` changed)."""
    got_state, nonce = login(client, platform)
    token = token_for(nonce) if token_for else platform.sign(platform.claims(nonce, **claims))
    return client.post(
        "/lti/launch",
        data={"id_token": token, "state": state if state is not None else got_state},
        follow_redirects=False,
    )


@contextmanager
def tool_client(data: Path, **settings_: Any) -> Iterator[TestClient]:
    """PAL Trainer (the tool) with the PAL milling exercises, on a fresh database under `data`."""
    from server.app import create_app
    from server.config import Settings

    settings = Settings(
        data_dir=data / "data",
        secret_key="lti-test-secret-of-at-least-thirty-two-bytes",
        workers=1,
        exercises_dir=Path(__file__).resolve().parents[1] / "exercises" / "pal-mill",
        **settings_,
    )
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as c:
        yield c


def registered_platform(client: TestClient) -> Platform:
    """A platform installed (its JWKS served to the tool) and registered with the tool."""
    p = Platform()
    install(client, p)
    register(client, p)
    return p
