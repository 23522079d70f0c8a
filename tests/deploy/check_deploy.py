#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Static checks of the container and deployment files (Dockerfile, deploy/).

    check_deploy.py ROOT yamllint|manifests|kustomize|compose|dockerfile|flags [DEPATHD]

Each check exits 0 on success, 1 with the problems listed, and 77 (ctest's skip code)
when a tool it needs is missing, so a bare machine skips instead of failing mysteriously.
`manifests` renders the kustomization itself (resources + configMapGenerator) so the
structure is checked even without kubectl; `kustomize` checks kubectl's own rendering.
"""
import re
import shutil
import subprocess
import sys
from pathlib import Path

SKIP = 77
DATA_DIR = "/var/lib/depath"
GRPC_PORT = 50051


def skip(why):
    print(f"SKIP: {why}")
    sys.exit(SKIP)


def load_yaml_all(text):
    try:
        import yaml
    except ImportError:
        skip("python3-yaml is not installed")
    return [d for d in yaml.safe_load_all(text) if d is not None]


class Problems(list):
    def check(self, cond, msg):
        if not cond:
            self.append(msg)
        return cond


# ---- Kubernetes -------------------------------------------------------------------------
def render_kustomization(k8s_dir, problems):
    """Minimal kustomize: the resources list, configMapGenerator literals, images."""
    kust = load_yaml_all((k8s_dir / "kustomization.yaml").read_text())[0]
    docs = []
    listed = set()
    for res in kust.get("resources", []):
        path = k8s_dir / res
        listed.add(path.name)
        if problems.check(path.is_file(), f"kustomization lists missing resource {res}"):
            docs += load_yaml_all(path.read_text())
    for f in sorted(k8s_dir.glob("*.y*ml")):
        problems.check(f.name in listed or f.name.startswith("kustomization"),
                       f"{f.name} is not listed in kustomization resources")
    for gen in kust.get("configMapGenerator", []):
        data = dict(lit.split("=", 1) for lit in gen.get("literals", []))
        docs.append({"apiVersion": "v1", "kind": "ConfigMap",
                     "metadata": {"name": gen["name"]}, "data": data})
    images = {i["name"]: i for i in kust.get("images", [])}
    for d in docs:
        for c in pod_spec(d).get("containers", []):
            img = images.get(c.get("image"))
            if img:
                c["image"] = f'{img.get("newName", c["image"])}:{img.get("newTag", "latest")}'
    return docs


def pod_spec(doc):
    return doc.get("spec", {}).get("template", {}).get("spec", {}) if doc.get(
        "kind") == "Deployment" else {}


def check_manifests(docs, problems):
    by_kind = {}
    for d in docs:
        by_kind.setdefault(d.get("kind"), []).append(d)
    for kind in ("Deployment", "Service", "PodDisruptionBudget", "ConfigMap"):
        problems.check(len(by_kind.get(kind, [])) == 1, f"expected exactly one {kind}")
    if problems:
        return
    dep, svc, pdb, cm = (by_kind[k][0] for k in
                         ("Deployment", "Service", "PodDisruptionBudget", "ConfigMap"))
    flags = {k: str(v) for k, v in cm.get("data", {}).items()}
    pod_labels = dep["spec"]["template"]["metadata"].get("labels", {})
    spec = pod_spec(dep)
    problems.check(dep["spec"].get("selector", {}).get("matchLabels", {}).items()
                   <= pod_labels.items(), "Deployment selector does not match its pods")
    problems.check(dep["spec"].get("replicas", 1) >= 2,
                   "Deployment should run >= 2 replicas (PDB, round_robin)")
    problems.check(spec.get("securityContext", {}).get("runAsNonRoot") is True,
                   "pod must set runAsNonRoot")
    (c,) = spec["containers"]
    problems.check(bool(c.get("image")), "container has no image")
    env_refs = [e["configMapRef"]["name"] for e in c.get("envFrom", []) if "configMapRef" in e]
    problems.check(cm["metadata"]["name"] in env_refs, "container does not read the ConfigMap")
    args = [str(a) for a in c.get("args", [])]
    for var in re.findall(r"\$\((\w+)\)", " ".join(args)):
        problems.check(var in flags, f"args use $({var}) but the ConfigMap lacks it")
    expanded = [re.sub(r"\$\((\w+)\)", lambda m: flags.get(m.group(1), ""), a) for a in args]
    arg_map = dict(a.split("=", 1) for a in expanded if a.startswith("--") and "=" in a)
    problems.check(arg_map.get("--data-dir") == DATA_DIR, f"--data-dir should be {DATA_DIR}")
    problems.check(any(m.get("mountPath") == DATA_DIR for m in c.get("volumeMounts", [])),
                   f"no volume mounted at {DATA_DIR}")
    ports = {p.get("name"): p.get("containerPort") for p in c.get("ports", [])}
    problems.check(ports.get("grpc") == GRPC_PORT, f"container port 'grpc' should be {GRPC_PORT}")
    for probe in ("livenessProbe", "readinessProbe"):
        port = c.get(probe, {}).get("grpc", {}).get("port")
        problems.check(port in (GRPC_PORT, "grpc"), f"{probe} must be a native grpc probe")
    for kind in ("requests", "limits"):
        res = c.get("resources", {}).get(kind, {})
        problems.check("cpu" in res and "memory" in res, f"resources.{kind} needs cpu and memory")
    # The kubelet must not SIGKILL a server that is still inside its shutdown bound.
    shutdown = int(arg_map.get("--shutdown-timeout-seconds", "10"))
    pre_stop = c.get("lifecycle", {}).get("preStop", {}).get("exec", {}).get("command", [])
    pre_stop_s = int(pre_stop[1]) if len(pre_stop) == 2 and pre_stop[0] == "sleep" else 0
    grace = spec.get("terminationGracePeriodSeconds", 30)
    problems.check(grace > shutdown + pre_stop_s,
                   f"terminationGracePeriodSeconds {grace} <= shutdown {shutdown}"
                   f" + preStop {pre_stop_s}")
    # Headless, so DNS lists every pod and gRPC round_robin can spread the calls.
    problems.check(svc["spec"].get("clusterIP") == "None", "Service must be headless")
    problems.check(svc["spec"].get("selector", {}).items() <= pod_labels.items() and
                   bool(svc["spec"].get("selector")), "Service selector does not match pods")
    problems.check(any(p.get("port") == GRPC_PORT for p in svc["spec"].get("ports", [])),
                   f"Service does not expose {GRPC_PORT}")
    problems.check(pdb.get("apiVersion") == "policy/v1", "PDB should be policy/v1")
    problems.check(pdb["spec"].get("selector", {}).get("matchLabels", {}).items()
                   <= pod_labels.items(), "PDB selector does not match pods")
    problems.check("minAvailable" in pdb["spec"] or "maxUnavailable" in pdb["spec"],
                   "PDB needs minAvailable or maxUnavailable")


# ---- Dockerfile -------------------------------------------------------------------------
def dockerfile_instructions(text):
    """(INSTRUCTION, args) pairs, continuation lines joined, comments dropped."""
    out, cur = [], ""
    for line in text.splitlines():
        if not cur and (not line.strip() or line.lstrip().startswith("#")):
            continue
        if line.lstrip().startswith("#"):
            continue
        cur += line.rstrip()
        if cur.endswith("\\"):
            cur = cur[:-1] + " "
            continue
        word, _, rest = cur.strip().partition(" ")
        out.append((word.upper(), rest.strip()))
        cur = ""
    return out


def read_packages(path):
    return [ln.strip() for ln in path.read_text().splitlines()
            if ln.strip() and not ln.lstrip().startswith("#")]


def check_dockerfile(root, problems):
    instrs = dockerfile_instructions((root / "Dockerfile").read_text())
    packages = read_packages(root / "scripts/packages.txt")
    for p in packages:
        problems.check(re.fullmatch(r"[a-z0-9][a-z0-9+.-]+", p) is not None,
                       f"packages.txt: {p!r} is not a package name")
    stages = [a for i, a in instrs if i == "FROM"]
    problems.check(len(stages) >= 2, "Dockerfile must be multi-stage")
    problems.check(stages and stages[0].split()[0] == "debian:bookworm",
                   "builder stage must be FROM debian:bookworm")
    problems.check(stages and stages[-1].split()[0] == "debian:bookworm-slim",
                   "runtime stage must be FROM debian:bookworm-slim")
    # One package list: the builder copies scripts/packages.txt and installs from it,
    # and no apt-get install anywhere names a package of that list by hand.
    builder = []
    for i, a in instrs[1:]:
        if i == "FROM":
            break
        builder.append((i, a))
    problems.check(any(i == "COPY" and "scripts/packages.txt" in a for i, a in builder),
                   "builder stage does not COPY scripts/packages.txt")
    problems.check(any(i == "RUN" and "packages.txt" in a and "apt-get install" in a
                       for i, a in builder),
                   "builder stage does not apt-get install from packages.txt")
    problems.check(any(i == "RUN" and "ctest" in a for i, a in builder),
                   "builder stage does not run the unit tests")
    for i, a in instrs:
        if i != "RUN":
            continue
        for cmd in re.findall(r"apt-get install([^;&|]*)", a):
            named = [w for w in cmd.split() if not w.startswith("-")]
            for w in named:
                problems.check(w not in packages,
                               f"Dockerfile installs {w} by hand; it belongs in packages.txt")
    last = instrs[max(k for k, (i, _) in enumerate(instrs) if i == "FROM"):]
    final = {i: a for i, a in last}  # last of each instruction in the runtime stage
    user = final.get("USER", "root").split(":")[0]
    problems.check(user not in ("", "root", "0"), "runtime stage must run as a non-root USER")
    problems.check(final.get("ENTRYPOINT", "").startswith("["), "ENTRYPOINT must be exec form")
    problems.check("depathd" in final.get("ENTRYPOINT", ""), "ENTRYPOINT must start depathd")
    problems.check(str(GRPC_PORT) in final.get("EXPOSE", ""), f"EXPOSE {GRPC_PORT} missing")
    problems.check("depath health" in final.get("HEALTHCHECK", ""),
                   "HEALTHCHECK must use depath health")
    problems.check(final.get("STOPSIGNAL", "SIGTERM") in ("SIGTERM", "15"),
                   "STOPSIGNAL must be SIGTERM")
    # docker stop waits 10 s by default; the default shutdown bound must fit inside it.
    m = re.search(r'"--shutdown-timeout-seconds"\s*,\s*"(\d+)"', final.get("CMD", ""))
    problems.check(m is not None and int(m.group(1)) < 10,
                   "CMD should set --shutdown-timeout-seconds below docker's 10 s stop timeout")


# ---- compose ----------------------------------------------------------------------------
def duration_s(v):
    m = re.fullmatch(r"(?:(\d+)m)?(?:(\d+)s)?", str(v))
    return int(m.group(1) or 0) * 60 + int(m.group(2) or 0) if m else 0


def check_compose(root, problems):
    (doc,) = load_yaml_all((root / "deploy/compose.yaml").read_text())
    svc = doc.get("services", {}).get("depathd")
    if not problems.check(svc is not None, "compose has no depathd service"):
        return
    args = dict(a.split("=", 1) for a in svc.get("command", []) if "=" in a)
    problems.check(args.get("--data-dir") == DATA_DIR, f"--data-dir should be {DATA_DIR}")
    vols = [str(v) for v in svc.get("volumes", [])]
    named = [v.split(":")[0] for v in vols if v.endswith(":" + DATA_DIR)]
    problems.check(bool(named) and named[0] in (doc.get("volumes") or {}),
                   f"no named volume mounted at {DATA_DIR}")
    test = svc.get("healthcheck", {}).get("test", [])
    problems.check(test[1:3] == ["depath", "health"], "healthcheck must run depath health")
    shutdown = int(args.get("--shutdown-timeout-seconds", "10"))
    problems.check(duration_s(svc.get("stop_grace_period", "10s")) > shutdown,
                   "stop_grace_period must exceed --shutdown-timeout-seconds")


# ---- flags exist in depathd -------------------------------------------------------------
def check_flags(root, depathd, problems):
    if not depathd or not Path(depathd).is_file():
        skip("depathd is not built")
    out = subprocess.run([depathd, "--help"], capture_output=True, text=True, timeout=30)
    help_text = out.stdout + out.stderr
    # The flags handed to depathd: the image's CMD, compose's command, the pod's args.
    final_cmd = [a for i, a in dockerfile_instructions((root / "Dockerfile").read_text())
                 if i == "CMD"][-1]
    (compose,) = load_yaml_all((root / "deploy/compose.yaml").read_text())
    (deployment,) = [d for d in load_yaml_all((root / "deploy/k8s/deployment.yaml").read_text())
                     if d.get("kind") == "Deployment"]
    args = re.findall(r'"(--[a-z-]+)"', final_cmd)
    args += [str(a) for a in compose["services"]["depathd"].get("command", [])]
    args += [str(a) for c in pod_spec(deployment)["containers"] for a in c.get("args", [])]
    used = {a.split("=", 1)[0] for a in args if a.startswith("--")}
    for flag in sorted(used):
        problems.check(re.search(re.escape(flag) + r"\b", help_text) is not None,
                       f"depathd --help does not list {flag}")


def main():
    root, what = Path(sys.argv[1]), sys.argv[2]
    problems = Problems()
    if what == "yamllint":
        if not shutil.which("yamllint"):
            skip("yamllint is not installed")
        r = subprocess.run(["yamllint", "-s", "-c", str(root / "deploy/.yamllint.yaml"),
                            str(root / "deploy")])
        sys.exit(0 if r.returncode == 0 else 1)
    elif what == "manifests":
        check_manifests(render_kustomization(root / "deploy/k8s", problems), problems)
    elif what == "kustomize":
        kubectl = shutil.which("kubectl")
        if not kubectl:
            skip("kubectl (Debian: kubernetes-client) is not installed")
        r = subprocess.run([kubectl, "kustomize", str(root / "deploy/k8s")],
                           capture_output=True, text=True, timeout=120)
        if r.returncode != 0:
            print(r.stderr)
            sys.exit(1)
        check_manifests(load_yaml_all(r.stdout), problems)
    elif what == "compose":
        check_compose(root, problems)
    elif what == "dockerfile":
        check_dockerfile(root, problems)
    elif what == "flags":
        check_flags(root, sys.argv[3] if len(sys.argv) > 3 else "", problems)
    else:
        sys.exit(f"unknown check {what}")
    for p in problems:
        print(f"FAIL: {p}")
    print("OK" if not problems else f"{len(problems)} problem(s)")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
