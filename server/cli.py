"""`paltrainer serve` and `paltrainer admin create-user|import-users|set-instructor|create-api-key|revoke-api-key|list-api-keys`.

Both honour the same settings as the server (DATABASE_URL, PALTRAINER_DATA_DIR, …); `admin`
migrates the database first, so it also works before the server has ever started.
"""

from __future__ import annotations

import argparse
import getpass
import os
import sys
from pathlib import Path
from typing import Any

from server.models import ROLES, SCOPES


def _serve(args: argparse.Namespace) -> int:
    import uvicorn

    from server.app import create_app
    from server.config import Settings
    from server.logs import configure

    settings = Settings()
    configure(settings.log_level)
    app = create_app(settings)
    print(
        f"PAL Trainer: http://{args.host}:{args.port}/docs  (API unter /api/v1, Daten: "
        f"{'DATABASE_URL' if settings.database_url else settings.data_dir.resolve()})",
        file=sys.stderr,
    )
    uvicorn.run(
        app,
        host=args.host,
        port=args.port,
        log_config=None,
        ws_max_size=settings.max_body_bytes,
        ws_per_message_deflate=False,
        proxy_headers=args.proxy_headers,
        forwarded_allow_ips=os.environ.get("FORWARDED_ALLOW_IPS"),
    )
    return 0


def register_serve(subparsers: Any, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "serve",
        help="Webserver starten / start the web server",
        description="Startet die Web-App und die REST-API (Einstellungen: docs/server.md).",
    )
    p.add_argument("--host", default="127.0.0.1", help="Adresse / address (Standard 127.0.0.1)")
    p.add_argument("--port", type=int, default=8000, help="Port (Standard 8000)")
    p.add_argument(
        "--proxy-headers",
        action="store_true",
        help="X-Forwarded-* eines Reverse-Proxys übernehmen / trust a reverse proxy's headers",
    )
    p.set_defaults(handler=_serve)


def _database() -> Any:
    from server.app import command_database

    return command_database()


def _lti_names(names: list[str]) -> bool:
    """Refuse (with a message) names an LTI launch would give: True if any of `names` is one."""
    from server.schemas import LTI_NAME_DE, LTI_NAME_EN, lti_reserved

    reserved = [n for n in names if lti_reserved(n)]
    for name in reserved:
        print(
            f"Name »{name}« nicht erlaubt: {LTI_NAME_DE} / name '{name}' not allowed: {LTI_NAME_EN}",
            file=sys.stderr,
        )
    return bool(reserved)


def _create_user(args: argparse.Namespace) -> int:
    from server import services
    from server.errors import ApiError
    from server.security import password_problem

    if _lti_names([args.name]):
        return 2
    password = args.password
    if password is None:
        password = getpass.getpass("Passwort / password: ")
    problem = password_problem(password)
    if problem is not None:
        print(f"{problem[0][0].upper()}{problem[0][1:]} / {problem[1]}", file=sys.stderr)
        return 2
    database = _database()
    with database.session() as db:
        try:
            instructor = services.instructor_named(db, args.instructor) if args.instructor else None
            user = services.create_user(db, args.name, password, args.role, instructor)
        except ApiError as err:
            print(f"{err.message} / {err.message_en}", file=sys.stderr)
            return 1
    managed = f", Lehrkraft / instructor {instructor.username}" if instructor else ""
    print(f"Benutzer {user.username} ({user.role}{managed}) angelegt / user created")
    return 0


def _migrate(args: argparse.Namespace) -> int:
    """The schema and the built-in exercises, once for many servers (the Kubernetes Job: deploy/kubernetes/)."""
    from server.app import prepare_database
    from server.config import Settings

    prepare_database(Settings()).engine.dispose()
    print("Datenbank ist aktuell / database is up to date")
    return 0


def _set_instructor(args: argparse.Namespace) -> int:
    from server import services
    from server.errors import ApiError

    database = _database()
    with database.session() as db:
        try:
            services.set_instructor(db, args.name, None if args.none else args.instructor)
        except ApiError as err:
            print(f"{err.message} / {err.message_en}", file=sys.stderr)
            return 1
    who = "niemand / nobody" if args.none else args.instructor
    print(f"{args.name}: Lehrkraft / instructor {who}")
    return 0


def _import_users(args: argparse.Namespace) -> int:
    """Students from a class list; prints name;password for each (generated passwords only now)."""
    from server import services
    from server.errors import ApiError

    try:
        data = sys.stdin.buffer.read() if args.file == "-" else Path(args.file).read_bytes()
    except OSError as err:
        print(f"»{args.file}« kann nicht gelesen werden: {err.strerror} / cannot read", file=sys.stderr)
        return 2
    database = _database()
    with database.session() as db:
        try:
            instructor = services.instructor_named(db, args.instructor) if args.instructor else None
            users = services.import_class_list(db, data, instructor)
        except ApiError as err:
            print(f"{err.message} / {err.message_en}", file=sys.stderr)
            for row in err.params.get("errors", [])[5:]:
                print(
                    f"Zeile {row['row']}: {row['message']} / row {row['row']}: {row['message_en']}",
                    file=sys.stderr,
                )
            return 1
    for u in users:
        print(f"{u.username};{u.password or ''}")
    print(
        f"{len(users)} Schüler angelegt (Passwörter werden nur jetzt angezeigt; leer: aus der Liste) / "
        f"{len(users)} students created (passwords shown only now; empty: from the list)",
        file=sys.stderr,
    )
    return 0


def _create_api_key(args: argparse.Namespace) -> int:
    from server import repository as repo
    from server import services

    database = _database()
    with database.session() as db:
        owner = None
        if args.user is not None:
            owner = repo.user_by_name(db, args.user)
            if owner is None:
                print(f"Benutzer »{args.user}« nicht gefunden / user not found", file=sys.stderr)
                return 1
        scopes = sorted({s for group in args.scope for s in group.split(",") if s})
        record, secret = services.create_api_key(db, args.name, scopes, owner)
    print(secret)
    print(
        f"API-Schlüssel {record.prefix} ({', '.join(scopes)}) – wird nur jetzt angezeigt / shown only now",
        file=sys.stderr,
    )
    return 0


def _list_api_keys(args: argparse.Namespace) -> int:
    from server import repository as repo

    database = _database()
    with database.session() as db:
        for k in repo.list_api_keys(db):
            state = "revoked" if k.revoked_at else "active"
            used = k.last_used_at.isoformat() if k.last_used_at else "-"
            print(f"{k.id}\t{k.prefix}\t{k.name}\t{','.join(k.scopes)}\t{state}\tlast used {used}")
    return 0


def _revoke_api_key(args: argparse.Namespace) -> int:
    from server import repository as repo

    database = _database()
    with database.session() as db:
        key = repo.api_key_by_prefix(db, args.prefix)
        if key is None:
            print(f"API-Schlüssel {args.prefix} nicht gefunden / API key not found", file=sys.stderr)
            return 1
        repo.revoke_api_key(db, key)
    print(f"API-Schlüssel {args.prefix} widerrufen / revoked")
    return 0


def _scope(text: str) -> str:
    for s in text.split(","):
        if s and s not in SCOPES:
            raise argparse.ArgumentTypeError(f"»{s}«: erlaubt sind / allowed: {', '.join(SCOPES)}")
    return text


def register_admin(subparsers: Any, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "admin", help="Benutzer und API-Schlüssel verwalten / manage users and API keys"
    )
    sub = p.add_subparsers(dest="admin_command", required=True)
    u = sub.add_parser("create-user", help="Benutzer anlegen / create a user")
    u.add_argument("name")
    u.add_argument("--role", choices=ROLES, default="student")
    u.add_argument("--password", help="ohne: wird abgefragt / without: asked for")
    u.add_argument(
        "--instructor",
        metavar="NAME",
        help="Lehrkraft, die den Benutzer betreut (sieht seine Abgaben) / the instructor who manages the user",
    )
    u.set_defaults(handler=_create_user)
    si = sub.add_parser("set-instructor", help="Lehrkraft eines Benutzers setzen / set a user's instructor")
    si.add_argument("name")
    group = si.add_mutually_exclusive_group(required=True)
    group.add_argument("instructor", nargs="?", help="die Lehrkraft / the instructor")
    group.add_argument("--none", action="store_true", help="keine Lehrkraft / no instructor")
    si.set_defaults(handler=_set_instructor)
    iu = sub.add_parser(
        "import-users",
        help="Klassenliste importieren / import a class list",
        description="CSV mit ; oder , (UTF-8, mit oder ohne BOM): Spalten name;password oder nur "
        "name, Kopfzeile erlaubt. Fehlende Passwörter werden erzeugt und einmal "
        "ausgegeben (name;passwort). Alles oder nichts.",
    )
    iu.add_argument("file", help="die CSV-Datei (- : Standardeingabe) / the CSV file (-: standard input)")
    iu.add_argument("--instructor", metavar="NAME", help="Lehrkraft der Klasse / the class's instructor")
    iu.set_defaults(handler=_import_users)
    k = sub.add_parser(
        "create-api-key", help="API-Schlüssel anlegen (wird einmal ausgegeben) / create an API key"
    )
    k.add_argument("name")
    k.add_argument(
        "--scope",
        action="append",
        type=_scope,
        required=True,
        help=f"mehrfach oder mit Komma / repeatable or comma-separated: {', '.join(SCOPES)}",
    )
    k.add_argument("--user", help="Der Schlüssel handelt für diesen Benutzer / the key acts for this user")
    k.set_defaults(handler=_create_api_key)
    lk = sub.add_parser("list-api-keys", help="API-Schlüssel auflisten / list API keys")
    lk.set_defaults(handler=_list_api_keys)
    m = sub.add_parser(
        "migrate",
        help="Datenbank auf den neuesten Stand bringen, Aufgaben laden / migrate the "
        "database and load the built-in exercises (before the servers start)",
    )
    m.set_defaults(handler=_migrate)
    r = sub.add_parser("revoke-api-key", help="API-Schlüssel widerrufen / revoke an API key")
    r.add_argument("prefix", help="the key's id after pal_, e.g. 1a2b3c4d")
    r.set_defaults(handler=_revoke_api_key)
    from server.lti.cli import register as register_lti

    register_lti(sub)  # lti-register, lti-platforms, lti-registration-url, lti-keys (docs/lti.md)
