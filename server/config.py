"""The server's settings: pydantic-settings, read from environment variables (documented in docs/server.md)."""

from __future__ import annotations

import secrets
from functools import cached_property
from pathlib import Path
from typing import Literal

from pydantic import AliasChoices, Field
from pydantic_settings import BaseSettings, SettingsConfigDict

from core.exercises import EXERCISES_DIR


class Settings(BaseSettings):
    """Every setting has an environment variable `PALTRAINER_<NAME>`; the database URL also `DATABASE_URL`."""

    model_config = SettingsConfigDict(env_prefix="PALTRAINER_", extra="ignore")

    database_url: str | None = Field(
        default=None, validation_alias=AliasChoices("DATABASE_URL", "PALTRAINER_DATABASE_URL")
    )
    # shared rate-limit and login-failure counts of all replicas (server/ratelimit.py); unset: kept in the process
    redis_url: str | None = Field(
        default=None, validation_alias=AliasChoices("REDIS_URL", "PALTRAINER_REDIS_URL")
    )
    # this server's name behind a load balancer: the 3D tokens start with it, so that the balancer sends a
    # scene's requests to the replica that holds it (deploy/haproxy.cfg); letters, digits and "-" only
    replica_id: str = Field(
        default="",
        pattern=r"^[A-Za-z0-9-]{0,63}$",
        validation_alias=AliasChoices("REPLICA_ID", "PALTRAINER_REPLICA_ID"),
    )
    data_dir: Path = Path("data")
    secret_key: str | None = None  # None: generated once and kept in <data_dir>/secret_key
    free_practice: bool = True  # check/run/simulate and the live socket without an account
    load_exercises: bool = True
    exercises_dir: Path = EXERCISES_DIR  # the repository's exercises/ next to core/
    token_minutes: int = 12 * 60
    cookie_secure: bool = False  # True behind HTTPS
    cors_origins: list[str] = []
    frame_ancestors: list[str] = []  # origins besides our own that may frame the pages (learning platforms)
    workers: int = 2  # worker processes for check/run/simulate/live
    job_seconds: float = 10.0  # time limit of one run/check/simulate/grade
    max_body_bytes: int = 1_000_000
    max_program_chars: int = 200_000
    max_live_lines: int = 20_000
    live_connections_per_user: int = (
        8  # open live sockets of one user or API key (tabs); beyond: closed with 4429
    )
    live_connections_per_address: int = (
        60  # open anonymous live sockets of one address (a class behind one NAT)
    )
    rate_login_per_minute: int = 5  # failed logins per user name (/auth/token and /auth/login together)
    rate_login_address_per_minute: int = 100  # failed logins per client address, whatever the user names
    rate_check_per_minute: int = 120  # check and run
    rate_simulate_per_minute: int = 30
    rate_submit_per_minute: int = 20
    rate_lti_login_per_minute: int = (
        300  # LTI launches started per address (a school's classes behind one NAT)
    )
    rate_join_per_minute: int = 10  # join-code tries of one user (POST /courses/join)
    rate_join_address_per_minute: int = 60  # join-code tries from one address, whoever asks
    # self-registration: "off", or "course-code" (a visitor makes a student account with a course's join code)
    self_signup: Literal["off", "course-code"] = "off"
    rate_signup_per_minute: int = (
        30  # sign-up tries from one address (a class behind one NAT registers at once)
    )
    rate_enrol_per_minute: int = 60  # members added by name (POST /courses/{id}/members), per user
    rate_draft_per_minute: int = 120  # draft saves (the editor saves at most every 2 s, per tab)
    # the 3D view: each live session is a viser server (a thread, a port, a few descriptors)
    rate_viz_per_minute: int = 60  # new 3D sessions (a class behind one school address reloads at once)
    rate_viz_scene_per_minute: int = 120  # scene and deviation: each runs the program in a worker
    rate_viz_playhead_per_minute: int = 900  # playback steps (5 a second while playing), views, layers
    rate_picture_per_minute: int = 60  # the exercise's picture and the picture of the current state
    # heavy requests (task sheets, pictures, drawings, submissions, simulations, 3D scenes and deviations) under
    # way at once, per user or API key and per address for anonymous ones; beyond: 429 TOO_MANY_JOBS
    heavy_jobs_per_user: int = Field(default=4, ge=1)
    heavy_jobs_per_address: int = Field(default=30, ge=1)  # anonymous free practice: a class behind one NAT
    submissions_with_details: int = Field(
        default=50, ge=1
    )  # per user and exercise the newest keep their diagnostics
    viz_sessions_per_user: int = (
        3  # live 3D sessions of one user (or key); beyond, the one idle longest stops
    )
    viz_sessions_per_address: int = 40  # live anonymous 3D sessions from one address (a class behind one NAT)
    viz_sessions_max: int = 200  # live 3D sessions in all
    viz_idle_seconds: float = 900.0  # a 3D session unused this long is stopped
    # how often the server looks for ended exams to submit their last drafts (pages say "wird abgegeben" till then)
    finalize_seconds: float = 3.0
    # a warning with the blocking code's stack when the event loop stops this long (server/loopwatch.py); 0: off
    loop_stall_seconds: float = Field(default=2.0, ge=0)
    log_level: str = "INFO"

    @cached_property
    def url(self) -> str:
        """The SQLAlchemy URL: DATABASE_URL (postgresql:// is driven by psycopg 3) or the SQLite file."""
        if self.database_url:
            url = self.database_url
            for prefix in ("postgres://", "postgresql://"):
                if url.startswith(prefix):
                    return "postgresql+psycopg://" + url[len(prefix) :]
            return url
        return f"sqlite:///{(self.data_dir / 'paltrainer.sqlite3').resolve()}"

    def jwt_secret(self) -> str:
        if self.secret_key:
            return self.secret_key
        path = self.data_dir / "secret_key"
        if path.exists():
            return path.read_text(encoding="utf-8").strip()
        self.data_dir.mkdir(parents=True, exist_ok=True)
        key = secrets.token_urlsafe(48)
        path.write_text(key, encoding="utf-8")
        path.chmod(0o600)
        return key
