"""Registering a platform: LTI Dynamic Registration (only with a registration URL from our admin), the admin
commands, and the tool keys stored encrypted with the server's secret."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from urllib.parse import urlencode

import httpx
import pytest
from fastapi.testclient import TestClient
from lti_testplatform import admin_headers
from sqlalchemy import select

from core.cli import main
from server.app import create_app
from server.config import Settings
from server.lti import keys
from server.models import LtiToolKey

ISSUER = "https://moodle.example.test"


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    tmp = tmp_path_factory.mktemp("lti-registration")
    settings = Settings(
        data_dir=tmp / "data",
        secret_key="lti-registration-secret-of-32-bytes-or-more",
        workers=1,
        load_exercises=False,
    )
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as c:
        yield c


def _moodle(seen: list[httpx.Request]) -> httpx.MockTransport:
    config = {
        "issuer": ISSUER,
        "authorization_endpoint": f"{ISSUER}/mod/lti/auth.php",
        "token_endpoint": f"{ISSUER}/mod/lti/token.php",
        "jwks_uri": f"{ISSUER}/mod/lti/certs.php",
        "registration_endpoint": f"{ISSUER}/mod/lti/openid-registration.php",
        "https://purl.imsglobal.org/spec/lti-platform-configuration": {
            "product_family_code": "moodle",
            "version": "4.3",
        },
    }

    def handler(request: httpx.Request) -> httpx.Response:
        seen.append(request)
        if request.url.path == "/mod/lti/openid-configuration.php":
            return httpx.Response(200, json=config)
        if request.url.path == "/mod/lti/openid-registration.php" and request.method == "POST":
            if request.headers.get("authorization") != "Bearer reg-token-1":
                return httpx.Response(401)
            return httpx.Response(
                200,
                json={
                    "client_id": "moodle-client-9",
                    **json.loads(request.content),
                    "https://purl.imsglobal.org/spec/lti-tool-configuration": {"deployment_id": "5"},
                },
            )
        return httpx.Response(404)

    return httpx.MockTransport(handler)


def test_dynamic_registration_needs_our_code_and_stores_the_platform(client: TestClient) -> None:
    seen: list[httpx.Request] = []
    client.app.state.lti_transport = _moodle(seen)  # type: ignore[attr-defined]
    params = {
        "openid_configuration": f"{ISSUER}/mod/lti/openid-configuration.php",
        "registration_token": "reg-token-1",
    }
    refused = client.get("/lti/register", params=params)
    assert refused.status_code == 403 and 'data-code="LTI_REGISTRATION_CODE"' in refused.text
    assert seen == []  # nothing was fetched for a request without our code
    url = client.post("/api/v1/admin/lti/registration-url", headers=admin_headers(client)).json()["url"]
    assert url.startswith("http://127.0.0.1/lti/register?code=")
    r = client.get(url.removeprefix("http://127.0.0.1") + "&" + urlencode(params))  # Moodle appends its own
    assert r.status_code == 200, r.text
    assert "PAL Trainer ist registriert" in r.text and '<script src="/lti/static/close.js"' in r.text
    posted = json.loads(seen[-1].content)
    assert posted["initiate_login_uri"] == "http://127.0.0.1/lti/login"
    assert posted["redirect_uris"] == ["http://127.0.0.1/lti/launch"]
    assert posted["jwks_uri"] == "http://127.0.0.1/lti/jwks"
    assert "https://purl.imsglobal.org/spec/lti-ags/scope/score" in posted["scope"].split()
    tool = posted["https://purl.imsglobal.org/spec/lti-tool-configuration"]
    assert tool["messages"][0]["type"] == "LtiDeepLinkingRequest"
    platforms = client.get("/api/v1/admin/lti/platforms", headers=admin_headers(client)).json()
    moodle = next(p for p in platforms if p["issuer"] == ISSUER)
    assert moodle["client_id"] == "moodle-client-9" and moodle["deployment_ids"] == ["5"]
    assert moodle["auth_login_url"] == f"{ISSUER}/mod/lti/auth.php"


def test_a_registration_url_registers_one_platform(client: TestClient) -> None:
    seen: list[httpx.Request] = []
    client.app.state.lti_transport = _moodle(seen)  # type: ignore[attr-defined]
    url = client.post("/api/v1/admin/lti/registration-url", headers=admin_headers(client)).json()["url"]
    path = url.removeprefix("http://127.0.0.1")
    params = {
        "openid_configuration": f"{ISSUER}/mod/lti/openid-configuration.php",
        "registration_token": "reg-token-1",
    }
    # opened without a platform's request (an admin trying the link): refused, and the URL still works
    r = client.get(path)
    assert r.status_code == 400 and 'data-code="LTI_REGISTRATION_INCOMPLETE"' in r.text
    assert client.get(path + "&" + urlencode(params)).status_code == 200
    fetched = len(seen)
    # the same URL again, e.g. by a second platform whose admin got hold of it: refused, nothing fetched
    again = client.get(path + "&" + urlencode(params))
    assert again.status_code == 403 and 'data-code="LTI_REGISTRATION_CODE"' in again.text
    assert "schon verwendet" in again.text
    assert len(seen) == fetched
    # a failed registration uses its URL up as well: the platform was contacted
    url = client.post("/api/v1/admin/lti/registration-url", headers=admin_headers(client)).json()["url"]
    other = {"openid_configuration": "https://other.example.test/mod/lti/openid-configuration.php"}
    path = url.removeprefix("http://127.0.0.1")
    assert client.get(path + "&" + urlencode(other)).status_code == 502
    assert client.get(path + "&" + urlencode(params)).status_code == 403


def test_dynamic_registration_refuses_a_configuration_of_another_site(client: TestClient) -> None:
    seen: list[httpx.Request] = []
    client.app.state.lti_transport = _moodle(seen)  # type: ignore[attr-defined]
    url = client.post("/api/v1/admin/lti/registration-url", headers=admin_headers(client)).json()["url"]
    # the configuration names ISSUER but is fetched from elsewhere: refused, nothing registered there
    other = {"openid_configuration": "https://other.example.test/mod/lti/openid-configuration.php"}
    r = client.get(url.removeprefix("http://127.0.0.1") + "&" + urlencode(other))
    assert r.status_code == 502 and 'data-code="LTI_REGISTRATION_FAILED"' in r.text


def test_admin_registration_validates_urls(client: TestClient) -> None:
    body = {
        "issuer": "https://x.example",
        "client_id": "c",
        "auth_login_url": "javascript:alert(1)",
        "token_url": "https://x.example/t",
        "jwks_url": "https://x.example/k",
    }
    r = client.post("/api/v1/admin/lti/platforms", json=body, headers=admin_headers(client))
    assert r.status_code == 422 and r.json()["error"]["code"] == "VALIDATION"
    # the issuer is an https URL too (LTI 1.3 core 5.1.2): it names the origin allowed to frame our pages
    body = {**body, "auth_login_url": "https://x.example/a", "issuer": "x.example; script-src *"}
    r = client.post("/api/v1/admin/lti/platforms", json=body, headers=admin_headers(client))
    assert r.status_code == 422 and r.json()["error"]["code"] == "VALIDATION"


def test_private_keys_are_stored_encrypted(client: TestClient) -> None:
    assert client.get("/lti/jwks").status_code == 200
    database = client.app.state.db  # type: ignore[attr-defined]
    with database.session() as db:
        row = db.scalars(select(LtiToolKey)).first()
        assert row is not None and "PRIVATE KEY" not in row.private_pem_encrypted
        kid, private = keys.signing_key(db)
        assert kid == row.kid and private.key_size == 2048
        assert "d" not in row.public_jwk  # only the public half is published


def test_cli_registers_platforms_and_rotates_keys(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("PALTRAINER_DATA_DIR", str(tmp_path / "data"))
    monkeypatch.delenv("DATABASE_URL", raising=False)
    args = [
        "admin",
        "lti-register",
        "--issuer",
        "https://ilias.example.test",
        "--client-id",
        "ilias-1",
        "--auth-url",
        "https://ilias.example.test/Services/LTI/auth.php",
        "--token-url",
        "https://ilias.example.test/Services/LTI/token.php",
        "--jwks-url",
        "https://ilias.example.test/Services/LTI/certs.php",
        "--deployment",
        "1",
    ]
    assert main(args) == 0
    assert main([*args[:-1], "2"]) == 0  # again: the deployment is added, the platform stays one
    assert main(["admin", "lti-platforms"]) == 0
    out = capsys.readouterr().out
    assert "https://ilias.example.test\tilias-1\t1,2" in out
    assert main(["admin", "lti-keys", "--rotate"]) == 0
    capsys.readouterr()
    assert main(["admin", "lti-keys", "--rotate"]) == 0
    out = capsys.readouterr().out
    assert out.count("current") == 1 and out.count("published") >= 1
    assert main(["admin", "lti-keys", "--retire", "no-such-kid"]) == 1
    bad = [*args[:5], "--auth-url", "http://ilias.example.test/auth.php", *args[7:]]
    assert main(bad) == 2
