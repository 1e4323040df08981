"""`paltrainer admin lti-register | lti-platforms | lti-registration-url | lti-keys`: platforms and tool keys
from the command line (the same as /api/v1/admin/lti/…)."""

from __future__ import annotations

import argparse
import sys
from typing import Any


def _database() -> Any:
    from server.app import command_database as database
    from server.config import Settings
    from server.lti import keys

    keys.configure(Settings())
    return database()


_OPTIONS = {
    "issuer": "--issuer",
    "client_id": "--client-id",
    "auth_login_url": "--auth-url",
    "token_url": "--token-url",
    "jwks_url": "--jwks-url",
    "deployment_ids": "--deployment",
    "name": "--name",
}


def _register(args: argparse.Namespace) -> int:
    from server.lti import registration

    fields = {
        "issuer": args.issuer,
        "client_id": args.client_id,
        "auth_login_url": args.auth_url,
        "token_url": args.token_url,
        "jwks_url": args.jwks_url,
        "deployment_ids": args.deployment or [],
        "name": args.name or "",
    }
    problems = registration.platform_problems(**fields)
    for field, (de, en) in problems.items():
        print(f"{_OPTIONS[field]}: {de} / {en}", file=sys.stderr)
    if problems:
        return 2
    with _database().session() as db:
        platform = registration.register(db, **fields)
        deps = registration.deployments(db, platform.id)
    print(
        f"Plattform {platform.id} registriert / platform registered: {platform.issuer} "
        f"(Client-ID {platform.client_id}, Deployments: {', '.join(deps) or '-'})"
    )
    return 0


def _platforms(args: argparse.Namespace) -> int:
    from server.lti import registration

    with _database().session() as db:
        for p in registration.platforms(db):
            print(
                f"{p.id}\t{p.issuer}\t{p.client_id}\t{','.join(registration.deployments(db, p.id))}\t{p.name}"
            )
    return 0


def _registration_url(args: argparse.Namespace) -> int:
    from server.config import Settings
    from server.lti.registration import registration_url

    print(registration_url(args.base_url.rstrip("/"), Settings()))
    print(
        "Gültig 7 Tage für eine Registrierung; in Moodle unter »Tool-URL« der dynamischen Registrierung "
        "eintragen / valid for 7 days and one registration",
        file=sys.stderr,
    )
    return 0


def _keys(args: argparse.Namespace) -> int:
    from server.lti import keys

    with _database().session() as db:
        if args.rotate:
            print(f"Neuer Schlüssel / new key: {keys.rotate(db).kid}")
        if args.retire and not keys.retire(db, args.retire):
            print(f"Schlüssel {args.retire} nicht gefunden / key not found", file=sys.stderr)
            db.rollback()
            return 1
        keys.jwks(db)  # there is always one key
        db.commit()
        for k in keys.listing(db):
            print(f"{k['kid']}\t{k['created_at']}\t{k['state']}")
    return 0


def register(sub: Any) -> None:
    """Add the LTI commands to `paltrainer admin`."""
    r = sub.add_parser(
        "lti-register", help="LTI-1.3-Plattform registrieren (Moodle, ILIAS …) / register an LTI platform"
    )
    r.add_argument("--issuer", required=True, help="Plattform-ID (iss), bei Moodle die Adresse der Site")
    r.add_argument("--client-id", required=True, help="Client-ID, die die Plattform vergeben hat")
    r.add_argument("--auth-url", required=True, help="Authentifizierungsanfrage-URL (OIDC) der Plattform")
    r.add_argument("--token-url", required=True, help="Access-Token-URL der Plattform")
    r.add_argument("--jwks-url", required=True, help="Öffentlicher Schlüsselsatz (JWKS-URL) der Plattform")
    r.add_argument("--deployment", action="append", help="Deployment-ID (mehrfach möglich) / deployment id")
    r.add_argument("--name", help="Anzeigename / display name")
    r.set_defaults(handler=_register)
    p = sub.add_parser("lti-platforms", help="Registrierte LTI-Plattformen auflisten / list LTI platforms")
    p.set_defaults(handler=_platforms)
    u = sub.add_parser(
        "lti-registration-url",
        help="URL für die dynamische Registrierung erzeugen / make a dynamic registration URL",
    )
    u.add_argument(
        "--base-url", required=True, help="öffentliche Adresse von PAL Trainer, z. B. https://pal.schule.de"
    )
    u.set_defaults(handler=_registration_url)
    k = sub.add_parser(
        "lti-keys", help="LTI-Schlüssel anzeigen, wechseln, zurückziehen / list, rotate, retire keys"
    )
    k.add_argument(
        "--rotate", action="store_true", help="neuen Schlüssel erzeugen (der alte bleibt veröffentlicht)"
    )
    k.add_argument("--retire", metavar="KID", help="Schlüssel aus /lti/jwks nehmen / retire a key")
    k.set_defaults(handler=_keys)
