"""LTI 1.3 Advantage: PAL Trainer as a tool in Moodle, ILIAS and other learning platforms (docs/lti.md).

registration.py: platforms and deployments (CLI, admin API, dynamic registration); keys.py: our RSA keys and
/lti/jwks; launch.py: OIDC login, id_token checks, users/courses/links from a launch; deep_linking.py: the
exercise picker's signed response; ags.py / nrps.py: grades back to the platform and its roster.
"""
