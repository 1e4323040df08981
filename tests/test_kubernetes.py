"""deploy/kubernetes/ (issue 21): every manifest is valid against the Kubernetes schemas (kubernetes-validate,
which bundles them: no network), strictly (no unknown fields), and the pieces fit together — the Deployment
reads the Secret's keys, probes /readyz and /healthz, the autoscaler and the disruption budget point at its
pods, the Service selects them, the 3D view's Ingress sticks by cookie, the migration Job runs the migration;
only the ingress controller reaches the app, and the app trusts forwarded addresses from nowhere else."""

from __future__ import annotations

import ipaddress
from pathlib import Path
from typing import Any

import kubernetes_validate
import pytest
import yaml

KUBE = Path(__file__).resolve().parent.parent / "deploy" / "kubernetes"
VERSION = "1.30.0"  # the oldest Kubernetes the manifests are for (ingress-nginx, autoscaling/v2, policy/v1)
MANIFESTS = sorted(p for p in KUBE.glob("*.yaml") if p.name != "kustomization.yaml")


def documents() -> list[dict[str, Any]]:
    return [doc for path in MANIFESTS for doc in yaml.safe_load_all(path.read_text(encoding="utf-8")) if doc]


def one(kind: str, name: str | None = None) -> dict[str, Any]:
    found = [d for d in documents() if d["kind"] == kind and (name is None or d["metadata"]["name"] == name)]
    assert len(found) == 1, (kind, name, len(found))
    return found[0]


@pytest.mark.parametrize("path", MANIFESTS, ids=lambda p: p.name)
def test_manifest_is_valid(path: Path) -> None:
    docs = [d for d in yaml.safe_load_all(path.read_text(encoding="utf-8")) if d]
    assert docs
    for doc in docs:
        kubernetes_validate.validate(doc, VERSION, strict=True)


def test_an_invalid_manifest_is_refused() -> None:
    bad = {**one("Deployment"), "spec": {**one("Deployment")["spec"], "replicas": "three"}}
    with pytest.raises(kubernetes_validate.ValidationError):
        kubernetes_validate.validate(bad, VERSION, strict=True)


def test_kustomization_lists_every_manifest() -> None:
    listed = yaml.safe_load((KUBE / "kustomization.yaml").read_text(encoding="utf-8"))["resources"]
    assert sorted(listed) == [p.name for p in MANIFESTS]


def test_the_pieces_fit() -> None:
    kinds = {d["kind"] for d in documents()}
    assert {
        "Deployment",
        "Service",
        "Ingress",
        "Job",
        "Secret",
        "PodDisruptionBudget",
        "HorizontalPodAutoscaler",
    } <= kinds
    deployment = one("Deployment")
    pod = deployment["spec"]["template"]
    labels = pod["metadata"]["labels"]
    app = pod["spec"]["containers"][0]
    assert deployment["spec"]["replicas"] >= 2
    assert app["readinessProbe"]["httpGet"]["path"] == "/readyz"
    assert app["livenessProbe"]["httpGet"]["path"] == "/healthz"
    assert app["resources"]["requests"]["cpu"] and app["resources"]["requests"]["memory"]
    env = {e["name"]: e for e in app["env"]}
    assert env["REPLICA_ID"]["valueFrom"]["fieldRef"]["fieldPath"] == "metadata.name"
    secret = one("Secret", "paltrainer")
    for name in ("DATABASE_URL", "REDIS_URL", "PALTRAINER_SECRET_KEY"):
        ref = env[name]["valueFrom"]["secretKeyRef"]
        assert ref["name"] == "paltrainer" and ref["key"] in secret["stringData"], name

    def selects(d: dict[str, Any]) -> dict[str, str]:
        return d["spec"]["selector"].get("matchLabels", d["spec"]["selector"])  # type: ignore[no-any-return]

    assert selects(one("Service", "paltrainer")).items() <= labels.items()
    assert selects(one("PodDisruptionBudget")).items() <= labels.items()
    hpa = one("HorizontalPodAutoscaler")
    assert hpa["spec"]["scaleTargetRef"]["name"] == deployment["metadata"]["name"]
    assert hpa["spec"]["metrics"][0]["resource"]["name"] == "cpu"
    job = one("Job")
    assert job["spec"]["template"]["spec"]["containers"][0]["command"] == ["paltrainer", "admin", "migrate"]


def test_the_3d_view_sticks_and_everything_has_tls() -> None:
    ingresses = {d["metadata"]["name"]: d for d in documents() if d["kind"] == "Ingress"}
    sticky = [
        i
        for i in ingresses.values()
        if i["metadata"]["annotations"].get("nginx.ingress.kubernetes.io/affinity") == "cookie"
    ]
    assert len(sticky) == 1
    paths = {p["path"] for rule in sticky[0]["spec"]["rules"] for p in rule["http"]["paths"]}
    assert paths == {"/viz/", "/api/v1/viz"}
    for ingress in ingresses.values():
        assert ingress["spec"]["tls"][0]["secretName"]
        assert ingress["spec"]["ingressClassName"] == "nginx"


def test_forwarded_addresses_are_trusted_from_the_ingress_only() -> None:
    """X-Forwarded-For decides whose budget a request uses up: a pod that could set it could use anyone's and
    spare its own. The app trusts it from the pod network only, and only the ingress controller may connect."""
    deployment = one("Deployment")
    pod = deployment["spec"]["template"]
    app = pod["spec"]["containers"][0]
    assert "--proxy-headers" in app["command"]
    trusted = {e["name"]: e for e in app["env"]}["FORWARDED_ALLOW_IPS"]["value"]
    networks = [ipaddress.ip_network(part.strip()) for part in trusted.split(",")]  # no "*", no host names
    assert networks and all(n.is_private and n.prefixlen >= 8 for n in networks), networks
    policies = [d for d in documents() if d["kind"] == "NetworkPolicy"]
    assert [p["metadata"]["name"] for p in policies] == ["paltrainer-web"]
    spec = policies[0]["spec"]
    assert spec["podSelector"]["matchLabels"].items() <= pod["metadata"]["labels"].items()
    assert spec["podSelector"]["matchLabels"] == one("Service", "paltrainer")["spec"]["selector"]
    assert spec["policyTypes"] == ["Ingress"]
    (rule,) = spec["ingress"]
    (peer,) = rule["from"]  # one peer: the controller's pods in the controller's namespace, both required
    assert set(peer) == {"namespaceSelector", "podSelector"}
    assert peer["namespaceSelector"]["matchLabels"] == {"kubernetes.io/metadata.name": "ingress-nginx"}
    assert peer["podSelector"]["matchLabels"]["app.kubernetes.io/name"] == "ingress-nginx"
    container_ports = {p["name"]: p["containerPort"] for p in app["ports"]}
    assert [(p["protocol"], container_ports.get(p["port"], p["port"])) for p in rule["ports"]] == [
        ("TCP", 8000)
    ]
    # the Ingress objects are served by that controller
    assert {i["spec"]["ingressClassName"] for i in documents() if i["kind"] == "Ingress"} == {"nginx"}
