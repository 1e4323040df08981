"""Deep linking: the instructor picks exercises, we answer the platform with a signed LtiDeepLinkingResponse
(LTI Deep Linking 2.0): one ltiResourceLink per exercise, custom `exercise=<slug>`, a line item of 100 points."""

from __future__ import annotations

import secrets
from datetime import UTC, datetime, timedelta
from typing import Any

import jwt
from sqlalchemy.orm import Session

from server.lti import keys
from server.lti.launch import CLAIM_DEPLOYMENT, CLAIM_MESSAGE_TYPE, CLAIM_VERSION
from server.models import Exercise, LtiLaunch, LtiPlatform

CLAIM_CONTENT_ITEMS = "https://purl.imsglobal.org/spec/lti-dl/claim/content_items"
CLAIM_DATA = "https://purl.imsglobal.org/spec/lti-dl/claim/data"
CLAIM_MSG = "https://purl.imsglobal.org/spec/lti-dl/claim/msg"
RESPONSE_SECONDS = 600
SCORE_MAXIMUM = 100


def content_item(exercise: Exercise, launch_url: str) -> dict[str, Any]:
    return {
        "type": "ltiResourceLink",
        "title": exercise.title_de,
        "text": exercise.title_en or exercise.title_de,
        "url": launch_url,
        "custom": {"exercise": exercise.slug},
        "lineItem": {
            "scoreMaximum": SCORE_MAXIMUM,
            "label": exercise.title_de,
            "resourceId": exercise.slug,
            "tag": "paltrainer",
        },
    }


def response_jwt(
    db: Session, launch: LtiLaunch, platform: LtiPlatform, exercises: list[Exercise], launch_url: str
) -> str:
    """The signed response (our current key, its kid in the header): iss is our client id, aud the platform."""
    kid, private = keys.signing_key(db)
    now = datetime.now(UTC)
    claims: dict[str, Any] = {
        "iss": platform.client_id,
        "aud": platform.issuer,
        "iat": now,
        "exp": now + timedelta(seconds=RESPONSE_SECONDS),
        "nonce": secrets.token_urlsafe(16),
        CLAIM_MESSAGE_TYPE: "LtiDeepLinkingResponse",
        CLAIM_VERSION: "1.3.0",
        CLAIM_DEPLOYMENT: launch.deployment_id,
        CLAIM_CONTENT_ITEMS: [content_item(e, launch_url) for e in exercises],
        CLAIM_MSG: f"{len(exercises)} Aufgabe(n) aus PAL Trainer eingefügt",
    }
    if launch.deep_link_data is not None:
        claims[CLAIM_DATA] = launch.deep_link_data
    return jwt.encode(claims, private, algorithm="RS256", headers={"kid": kid})
