#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Static checks of the container and deployment files (Dockerfile, deploy/).

    check_deploy.py ROOT yamllint|dockerfile
    check_deploy.py ROOT manifests|kustomize base|scale-out
    check_deploy.py ROOT compose single|postgres
    check_deploy.py ROOT flags DEPATHD

Each check exits 0 on success, 1 with the problems listed, and 77 (ctest's skip code)
when a tool it needs is missing, so a bare machine skips instead of failing mysteriously.
`manifests` renders a kustomization itself (resources incl. a base directory, generators,
strategic merge and JSON 6902 patches, images) so the structure is checked even without
kubectl; `kustomize` checks kubectl's own rendering of the same directory.
"""
import base64
import copy
import json
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
# The two kustomizations: the single-node base (SQLite on a PVC) and the scale-out overlay
# (PostgreSQL from a Secret). Each is checked as its own deployment.
SETUPS = {"base": "deploy/k8s/base", "scale-out": "deploy/k8s/scale-out"}
KNOWN_FIELDS = {"apiVersion", "kind", "resources", "configMapGenerator", "secretGenerator",
                "patches", "patchesStrategicMerge", "patchesJson6902", "images"}
# Strategic merge: lists of these fields merge item by item on the key; others are replaced.
MERGE_KEYS = {"containers": "name", "initContainers": "name", "volumes": "name", "env": "name",
              "volumeMounts": "mountPath", "ports": "containerPort",
              "topologySpreadConstraints": "topologyKey", "imagePullSecrets": "name"}


def strategic_merge(base, patch):
    """Kubernetes strategic merge patch, the subset kustomize overlays use: maps merge, null
    deletes a field, lists in MERGE_KEYS merge by key ("$patch: delete" drops an item),
    "$patch: replace" replaces a map, other lists are replaced."""
    if not isinstance(base, dict) or not isinstance(patch, dict):
        return copy.deepcopy(patch)
    if patch.get("$patch") == "replace":
        return {k: copy.deepcopy(v) for k, v in patch.items() if k != "$patch"}
    out = copy.deepcopy(base)
    for key, value in patch.items():
        if key == "$patch":
            continue
        if value is None:
            out.pop(key, None)
        elif key in MERGE_KEYS and isinstance(value, list) and isinstance(out.get(key), list):
            out[key] = merge_list(out[key], value, MERGE_KEYS[key])
        elif isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = strategic_merge(out[key], value)
        else:
            out[key] = strip_directives(value)
    return out


def merge_list(base, patch, key):
    out = copy.deepcopy(base)
    for item in patch:
        at = next((i for i, x in enumerate(out)
                   if isinstance(x, dict) and isinstance(item, dict) and
                   x.get(key) == item.get(key)), None)
        if isinstance(item, dict) and item.get("$patch") == "delete":
            if at is not None:
                out.pop(at)
        elif at is None:
            out.append(strip_directives(item))
        else:
            out[at] = strategic_merge(out[at], item)
    return out


def strip_directives(value):
    if isinstance(value, dict):
        return {k: strip_directives(v) for k, v in value.items() if not k.startswith("$patch")}
    if isinstance(value, list):
        return [strip_directives(v) for v in value]
    return copy.deepcopy(value)


def json6902(doc, ops, problems):
    """RFC 6902 add / remove / replace on one resource."""
    for op in ops:
        parts = [p.replace("~1", "/").replace("~0", "~") for p in op["path"].split("/")[1:]]
        parent = doc
        try:
            for p in parts[:-1]:
                parent = parent[int(p)] if isinstance(parent, list) else parent[p]
            last = parts[-1]
            if isinstance(parent, list):
                idx = len(parent) if last == "-" else int(last)
                if op["op"] == "add":
                    parent.insert(idx, copy.deepcopy(op["value"]))
                elif op["op"] == "remove":
                    parent.pop(idx)
                elif op["op"] == "replace":
                    parent[idx] = copy.deepcopy(op["value"])
                else:
                    problems.append(f"JSON patch op {op['op']} is not supported here")
            elif op["op"] in ("add", "replace"):
                if op["op"] == "replace" and last not in parent:
                    raise KeyError(last)
                parent[last] = copy.deepcopy(op["value"])
            elif op["op"] == "remove":
                del parent[last]
            else:
                problems.append(f"JSON patch op {op['op']} is not supported here")
        except (KeyError, IndexError, ValueError, TypeError):
            problems.append(f"JSON patch {op['op']} {op['path']}: path not found")


def generated(gen, kind, k_dir):
    data = {}
    for lit in gen.get("literals", []):
        k, v = lit.split("=", 1)
        data[k] = v
    for env in gen.get("envs", []) + ([gen["env"]] if "env" in gen else []):
        for line in (k_dir / env).read_text().splitlines():
            if line.strip() and not line.lstrip().startswith("#"):
                k, v = line.split("=", 1)
                data[k.strip()] = v
    for f in gen.get("files", []):
        k, _, path = f.rpartition("=")
        data[k or Path(path).name] = (k_dir / path).read_text()
    if kind == "Secret":
        data = {k: base64.b64encode(v.encode()).decode() for k, v in data.items()}
        return {"apiVersion": "v1", "kind": "Secret", "type": gen.get("type", "Opaque"),
                "metadata": {"name": gen["name"]}, "data": data}
    return {"apiVersion": "v1", "kind": "ConfigMap", "metadata": {"name": gen["name"]},
            "data": data}


def same_resource(doc, kind, name):
    return doc.get("kind") == kind and doc.get("metadata", {}).get("name") == name


def render_kustomization(k_dir, problems):
    """Minimal kustomize: resources (files and directories, recursively), config map and
    secret generators (literals, envs, files), patches (strategic merge, including
    "$patch: delete" of a whole resource, and JSON 6902 with a target), images."""
    kust = load_yaml_all((k_dir / "kustomization.yaml").read_text())[0]
    for field in set(kust) - KNOWN_FIELDS:
        problems.append(f"{k_dir.name}/kustomization.yaml: field {field} is not rendered by"
                        " check_deploy.py (teach it, or use a supported field)")
    docs, listed = [], set()
    for res in kust.get("resources", []):
        path = k_dir / res
        listed.add(path.name)
        if path.is_dir():
            docs += render_kustomization(path, problems)
        elif problems.check(path.is_file(), f"kustomization lists missing resource {res}"):
            docs += load_yaml_all(path.read_text())
    for gen in kust.get("configMapGenerator", []):
        docs.append(generated(gen, "ConfigMap", k_dir))
    for gen in kust.get("secretGenerator", []):
        docs.append(generated(gen, "Secret", k_dir))
    patches = [dict(p) for p in kust.get("patches", [])]
    patches += [{"path": p} for p in kust.get("patchesStrategicMerge", [])]
    patches += [dict(p) for p in kust.get("patchesJson6902", [])]
    for p in patches:
        if "path" in p:
            listed.add(Path(p["path"]).name)
            text = (k_dir / p["path"]).read_text()
        else:
            text = p.get("patch", "")
        body = load_yaml_all(text)
        target = p.get("target", {})
        if body and isinstance(body[0], list):  # JSON 6902
            hits = [d for d in docs if same_resource(d, target.get("kind"), target.get("name"))]
            problems.check(len(hits) == 1, f"JSON patch target {target} matches {len(hits)}")
            for d in hits:
                json6902(d, body[0], problems)
            continue
        for sm in body:
            kind = target.get("kind", sm.get("kind"))
            name = target.get("name", sm.get("metadata", {}).get("name"))
            hits = [i for i, d in enumerate(docs) if same_resource(d, kind, name)]
            if not problems.check(len(hits) == 1, f"patch of {kind}/{name} matches {len(hits)}"):
                continue
            if sm.get("$patch") == "delete":
                docs.pop(hits[0])
            else:
                docs[hits[0]] = strategic_merge(docs[hits[0]], sm)
    for f in sorted(k_dir.glob("*.y*ml")):
        problems.check(f.name in listed or f.name.startswith("kustomization"),
                       f"{k_dir.name}/{f.name} is not used by its kustomization")
    images = {i["name"]: i for i in kust.get("images", [])}
    for d in docs:
        for c in pod_spec(d).get("containers", []):
            img = images.get(c.get("image"))
            if img:
                c["image"] = f'{img.get("newName", c["image"])}:{img.get("newTag", "latest")}'
    return docs


def canonical(docs, generated_names):
    """Resources in a comparable form: generated names without kustomize's hash suffix,
    Secret data decoded, empty fields dropped, documents sorted."""
    names = "|".join(re.escape(n) for n in generated_names) or "(?!)"
    suffix = re.compile(rf"^({names})-[a-z0-9]{{10}}$")

    def norm(x):
        if isinstance(x, dict):
            return {k: norm(v) for k, v in x.items() if v not in ([], {}, None)}
        if isinstance(x, list):
            return [norm(v) for v in x]
        return suffix.sub(r"\1", x) if isinstance(x, str) else x

    out = []
    for d in map(norm, docs):
        if d.get("kind") == "Secret":
            d["data"] = {k: base64.b64decode(v).decode() for k, v in d.get("data", {}).items()}
        out.append(json.dumps(d, sort_keys=True))
    return sorted(out)


def pod_spec(doc):
    return doc.get("spec", {}).get("template", {}).get("spec", {}) if doc.get(
        "kind") == "Deployment" else {}


def labels_match(selector, labels):
    return bool(selector) and selector.items() <= labels.items()


def container_args(c, flags):
    """The container's args with $(VAR) expanded from its env and ConfigMap, as a dict."""
    args = [str(a) for a in c.get("args", [])]
    expanded = [re.sub(r"\$\((\w+)\)", lambda m: flags.get(m.group(1), ""), a) for a in args]
    return args, dict(a.split("=", 1) if "=" in a else (a, "") for a in expanded
                      if a.startswith("--"))


def check_manifests(docs, setup, problems):
    by_kind = {}
    for d in docs:
        by_kind.setdefault(d.get("kind"), []).append(d)
    for kind in ("Deployment", "Service"):
        problems.check(len(by_kind.get(kind, [])) == 1, f"expected exactly one {kind}")
    if problems:
        return
    dep, svc = by_kind["Deployment"][0], by_kind["Service"][0]
    config_maps = {d["metadata"]["name"]: d for d in by_kind.get("ConfigMap", [])}
    secrets = {d["metadata"]["name"]: d for d in by_kind.get("Secret", [])}
    pod_labels = dep["spec"]["template"]["metadata"].get("labels", {})
    spec = pod_spec(dep)
    problems.check(labels_match(dep["spec"].get("selector", {}).get("matchLabels", {}),
                                pod_labels), "Deployment selector does not match its pods")
    problems.check(spec.get("securityContext", {}).get("runAsNonRoot") is True,
                   "pod must set runAsNonRoot")
    (c,) = spec["containers"]
    problems.check(bool(c.get("image")), "container has no image")
    # A locally loaded image (no registry) must not be pulled; Kubernetes defaults a
    # :latest tag to Always, so the policy is stated.
    policy = c.get("imagePullPolicy")
    problems.check(policy in ("IfNotPresent", "Always", "Never"), "imagePullPolicy is not set")
    problems.check(not (str(c.get("image", "")).startswith("localhost/") and policy == "Always"),
                   "a localhost/ image cannot be pulled: imagePullPolicy must not be Always")
    env_refs = [e["configMapRef"]["name"] for e in c.get("envFrom", []) if "configMapRef" in e]
    flags = {}
    for ref in env_refs:
        if problems.check(ref in config_maps, f"envFrom names a missing ConfigMap {ref}"):
            flags.update({k: str(v) for k, v in config_maps[ref].get("data", {}).items()})
    env = {e["name"]: e for e in c.get("env", [])}
    flags.update({k: str(e["value"]) for k, e in env.items() if "value" in e})
    args, arg_map = container_args(c, flags)
    for var in re.findall(r"\$\((\w+)\)", " ".join(args)):
        problems.check(var in flags, f"args use $({var}) but neither env nor ConfigMap has it")
    problems.check(arg_map.get("--data-dir") == DATA_DIR, f"--data-dir should be {DATA_DIR}")
    ports = {p.get("name"): p.get("containerPort") for p in c.get("ports", [])}
    problems.check(ports.get("grpc") == GRPC_PORT, f"container port 'grpc' should be {GRPC_PORT}")
    for probe in ("startupProbe", "livenessProbe", "readinessProbe"):
        port = c.get(probe, {}).get("grpc", {}).get("port")
        problems.check(port in (GRPC_PORT, "grpc"), f"{probe} must be a native grpc probe")
    for kind in ("requests", "limits"):
        res = c.get("resources", {}).get(kind, {})
        problems.check("cpu" in res and "memory" in res, f"resources.{kind} needs cpu and memory")
    # The kubelet must not SIGKILL a server that is still inside its shutdown bound (in
    # which a running job writes its checkpoint and hands itself back to the store).
    shutdown = float(arg_map.get("--shutdown-timeout-seconds", "10"))
    pre_stop = c.get("lifecycle", {}).get("preStop", {}).get("exec", {}).get("command", [])
    pre_stop_s = int(pre_stop[1]) if len(pre_stop) == 2 and pre_stop[0] == "sleep" else 0
    grace = spec.get("terminationGracePeriodSeconds", 30)
    problems.check(grace > shutdown + pre_stop_s,
                   f"terminationGracePeriodSeconds {grace} <= shutdown {shutdown}"
                   f" + preStop {pre_stop_s}")
    # Headless, so DNS lists every pod and gRPC round_robin can spread the calls.
    problems.check(svc["spec"].get("clusterIP") == "None", "Service must be headless")
    problems.check(labels_match(svc["spec"].get("selector", {}), pod_labels),
                   "Service selector does not match pods")
    problems.check(any(p.get("port") == GRPC_PORT for p in svc["spec"].get("ports", [])),
                   f"Service does not expose {GRPC_PORT}")
    mounts = {m.get("name"): m.get("mountPath") for m in c.get("volumeMounts", [])}
    pvcs = by_kind.get("PersistentVolumeClaim", [])
    claim_volumes = {v["name"]: v["persistentVolumeClaim"].get("claimName")
                     for v in spec.get("volumes", []) if "persistentVolumeClaim" in v}
    replicas = dep["spec"].get("replicas", 1)
    strategy = dep["spec"].get("strategy", {}).get("type", "RollingUpdate")
    if setup == "base":
        # One server per SQLite file: one pod, the old one gone before the new one starts,
        # the store on a claim mounted at the data directory.
        problems.check(replicas == 1, f"base must run 1 replica (SQLite), not {replicas}")
        problems.check(strategy == "Recreate", "base strategy must be Recreate (one SQLite file)")
        problems.check("--store" not in arg_map and "DEPATHD_STORE" not in env,
                       "base must use the default SQLite store in --data-dir")
        problems.check(len(pvcs) == 1, "base needs one PersistentVolumeClaim")
        pvc_names = {p["metadata"]["name"] for p in pvcs}
        problems.check(any(claim in pvc_names and mounts.get(vol) == DATA_DIR
                           for vol, claim in claim_volumes.items()),
                       f"the PersistentVolumeClaim is not mounted at {DATA_DIR}")
        for p in pvcs:
            problems.check("ReadWriteOnce" in p["spec"].get("accessModes", []),
                           "the PVC should be ReadWriteOnce (one server per SQLite file)")
            problems.check("storage" in p["spec"].get("resources", {}).get("requests", {}),
                           "the PVC requests no storage")
        problems.check(not by_kind.get("HorizontalPodAutoscaler"),
                       "base must not autoscale (one server per SQLite file)")
        return
    # scale-out: interchangeable replicas on PostgreSQL.
    problems.check(replicas >= 2, f"scale-out should run >= 2 replicas, not {replicas}")
    problems.check(strategy == "RollingUpdate", "scale-out should roll (RollingUpdate)")
    problems.check("--store" not in arg_map, "a --store flag would override DEPATHD_STORE")
    ref = env.get("DEPATHD_STORE", {}).get("valueFrom", {}).get("secretKeyRef", {})
    if problems.check(bool(ref), "DEPATHD_STORE must come from a Secret (secretKeyRef)"):
        secret = secrets.get(ref.get("name"), {})
        raw = secret.get("data", {}).get(ref.get("key"))
        if problems.check(raw is not None, f"Secret {ref.get('name')} lacks {ref.get('key')}"):
            dsn = base64.b64decode(raw).decode()
            problems.check(re.match(r"postgres(ql)?://", dsn) is not None,
                           "DEPATHD_STORE in the Secret is not a postgresql:// URI")
    problems.check(not pvcs and not claim_volumes,
                   "scale-out needs no PersistentVolumeClaim (the state is in PostgreSQL)")
    spreads = spec.get("topologySpreadConstraints", [])
    problems.check(any(labels_match(s.get("labelSelector", {}).get("matchLabels", {}),
                                    pod_labels) and s.get("topologyKey") ==
                       "kubernetes.io/hostname" for s in spreads),
                   "scale-out should spread replicas over nodes (topologySpreadConstraints)")
    pdbs = by_kind.get("PodDisruptionBudget", [])
    if problems.check(len(pdbs) == 1, "scale-out needs one PodDisruptionBudget"):
        pdb = pdbs[0]
        problems.check(pdb.get("apiVersion") == "policy/v1", "PDB should be policy/v1")
        problems.check(labels_match(pdb["spec"].get("selector", {}).get("matchLabels", {}),
                                    pod_labels), "PDB selector does not match pods")
        max_un = pdb["spec"].get("maxUnavailable")
        min_av = pdb["spec"].get("minAvailable")
        problems.check((isinstance(max_un, int) and 1 <= max_un < replicas) or
                       (isinstance(min_av, int) and 1 <= min_av < replicas),
                       "PDB must keep a replica up and still allow a drain")
    hpas = by_kind.get("HorizontalPodAutoscaler", [])
    if problems.check(len(hpas) == 1, "scale-out needs one HorizontalPodAutoscaler"):
        hpa = hpas[0]["spec"]
        problems.check(hpas[0].get("apiVersion") == "autoscaling/v2", "HPA should be autoscaling/v2")
        target = hpa.get("scaleTargetRef", {})
        problems.check(target.get("kind") == "Deployment" and target.get("apiVersion") ==
                       "apps/v1" and target.get("name") == dep["metadata"]["name"],
                       "HPA scaleTargetRef does not name the Deployment")
        lo, hi = hpa.get("minReplicas", 1), hpa.get("maxReplicas", 0)
        problems.check(2 <= lo <= hi, f"HPA needs 2 <= minReplicas {lo} <= maxReplicas {hi}")
        metrics = hpa.get("metrics", [])
        problems.check(bool(metrics), "HPA has no metrics")
        requests = c.get("resources", {}).get("requests", {})
        for m in metrics:
            if m.get("type") == "Resource":
                name = m.get("resource", {}).get("name")
                problems.check(name in requests,
                               f"HPA scales on {name} but the container requests none")
                problems.check(m["resource"].get("target", {}).get("type") in
                               ("Utilization", "AverageValue"), "HPA resource target type")


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
COMPOSE = {"single": "deploy/compose.yaml", "postgres": "deploy/compose.postgres.yaml"}


def duration_s(v):
    m = re.fullmatch(r"(?:(\d+)m)?(?:(\d+)s)?", str(v))
    return int(m.group(1) or 0) * 60 + int(m.group(2) or 0) if m else 0


def depathd_services(doc):
    """Services that run the depath image (their command is depathd's flags)."""
    return {n: s for n, s in doc.get("services", {}).items()
            if "depath" in str(s.get("image", "")) and "postgres" not in str(s.get("image"))}


def check_depathd_service(name, svc, problems):
    args = dict(a.split("=", 1) for a in svc.get("command", []) if "=" in a)
    test = svc.get("healthcheck", {}).get("test", [])
    problems.check(test[1:3] == ["depath", "health"], f"{name}: healthcheck must run depath health")
    shutdown = float(args.get("--shutdown-timeout-seconds", "10"))
    problems.check(duration_s(svc.get("stop_grace_period", "10s")) > shutdown,
                   f"{name}: stop_grace_period must exceed --shutdown-timeout-seconds")
    return args


def check_compose(root, variant, problems):
    (doc,) = load_yaml_all((root / COMPOSE[variant]).read_text())
    services = depathd_services(doc)
    declared_volumes = doc.get("volumes") or {}
    if variant == "single":
        svc = services.get("depathd")
        if not problems.check(len(services) == 1 and svc is not None,
                              "compose.yaml should run one depathd service"):
            return
        args = check_depathd_service("depathd", svc, problems)
        # The store: SQLite in the data directory, on a named volume.
        problems.check(args.get("--data-dir") == DATA_DIR, f"--data-dir should be {DATA_DIR}")
        problems.check(args.get("--store", "sqlite:").startswith("sqlite:"),
                       "compose.yaml is the SQLite setup")
        vols = [str(v) for v in svc.get("volumes", [])]
        named = [v.split(":")[0] for v in vols if v.endswith(":" + DATA_DIR)]
        problems.check(bool(named) and named[0] in declared_volumes,
                       f"no named volume mounted at {DATA_DIR}")
        return
    pg = doc.get("services", {}).get("postgres")
    if not problems.check(pg is not None, "compose.postgres.yaml has no postgres service"):
        return
    # Built from Debian's packages (deploy/postgres), like depath's own image: no registry.
    build = pg.get("build", {})
    context = build.get("context") if isinstance(build, dict) else build
    problems.check(context is not None and (root / "deploy" / str(context) / "Dockerfile").is_file(),
                   "postgres service should be built from deploy/postgres/Dockerfile")
    if context is not None and (root / "deploy" / str(context) / "Dockerfile").is_file():
        dockerfile = (root / "deploy" / str(context) / "Dockerfile").read_text()
        problems.check("FROM debian:bookworm" in dockerfile and "postgresql-15" in dockerfile,
                       "deploy/postgres/Dockerfile should install Debian 12's postgresql-15")
    problems.check("pg_isready" in " ".join(map(str, pg.get("healthcheck", {}).get("test", []))),
                   "postgres healthcheck must run pg_isready")
    pg_vols = [str(v).split(":") for v in pg.get("volumes", [])]
    problems.check(any(v[0] in declared_volumes and v[1] == "/var/lib/postgresql/data"
                       for v in pg_vols if len(v) >= 2),
                   "postgres data needs a named volume at /var/lib/postgresql/data")
    pg_env = pg.get("environment", {})
    password = str(pg_env.get("POSTGRES_PASSWORD", ""))
    problems.check("POSTGRES_PASSWORD_FILE" in pg_env or password.startswith("${"),
                   "the PostgreSQL password must come from the environment or a secret,"
                   " not a literal")
    problems.check(len(services) >= 2, f"expected >= 2 depathd replicas, got {len(services)}")
    host_ports = []
    for name, svc in services.items():
        args = check_depathd_service(name, svc, problems)
        store = args.get("--store", "")
        problems.check(store.startswith("postgresql://") and "@postgres:" in store,
                       f"{name}: --store must be postgresql://...@postgres:PORT/DB")
        problems.check(re.match(r"postgresql://[^/@:]*@", store) is not None,
                       f"{name}: no password in --store (flags are visible in ps)")
        cond = (svc.get("depends_on") or {}).get("postgres", {})
        problems.check(isinstance(cond, dict) and cond.get("condition") == "service_healthy",
                       f"{name}: depends_on postgres must wait for service_healthy")
        problems.check(str(svc.get("environment", {}).get("PGPASSWORD", "")).startswith("${"),
                       f"{name}: PGPASSWORD should come from the environment")
        host_ports += [str(p).rsplit(":", 1)[0] for p in svc.get("ports", [])]
    problems.check(len(host_ports) == len(set(host_ports)), "replicas publish the same host port")


# ---- flags exist in depathd -------------------------------------------------------------
def check_flags(root, depathd, problems):
    if not depathd or not Path(depathd).is_file():
        skip("depathd is not built")
    out = subprocess.run([depathd, "--help"], capture_output=True, text=True, timeout=30)
    help_text = out.stdout + out.stderr
    # The flags handed to depathd: the image's CMD, compose's commands, the pods' args; and
    # the DEPATHD_* environment variables they set.
    final_cmd = [a for i, a in dockerfile_instructions((root / "Dockerfile").read_text())
                 if i == "CMD"][-1]
    args = re.findall(r'"(--[a-z-]+)"', final_cmd)
    env_names = set()
    for variant in COMPOSE:
        (compose,) = load_yaml_all((root / COMPOSE[variant]).read_text())
        for svc in depathd_services(compose).values():
            args += [str(a) for a in svc.get("command", [])]
            env_names |= set(svc.get("environment", {}) or {})
    for setup in SETUPS:
        for d in render_kustomization(root / SETUPS[setup], problems):
            for c in pod_spec(d).get("containers", []):
                args += [str(a) for a in c.get("args", [])]
                env_names |= {e["name"] for e in c.get("env", [])}
    used = {a.split("=", 1)[0] for a in args if a.startswith("--")}
    problems.check(len(used) >= 10, f"found only {len(used)} flags: is the parsing broken?")
    for flag in sorted(used):
        problems.check(re.search(re.escape(flag) + r"\b", help_text) is not None,
                       f"depathd --help does not list {flag}")
    for name in sorted(n for n in env_names if n.startswith("DEPATHD_")):
        problems.check(f"Env:{name}" in help_text, f"depathd --help names no env var {name}")


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
        setup = sys.argv[3]
        check_manifests(render_kustomization(root / SETUPS[setup], problems), setup, problems)
    elif what == "kustomize":
        setup = sys.argv[3]
        kubectl = shutil.which("kubectl")
        if not kubectl:
            skip("kubectl is not installed")
        # kubectl < 1.21 embeds kustomize v2, which cannot take a base directory in
        # resources: (and prints no "Kustomize Version"): that is a missing tool, not a defect.
        v = subprocess.run([kubectl, "version", "--client"], capture_output=True, text=True,
                           timeout=60).stdout
        m = re.search(r"Kustomize Version: v(\d+)", v)
        if not m or int(m.group(1)) < 4:
            skip("kubectl's kustomize is older than v4 (needs kubectl >= 1.21)")
        r = subprocess.run([kubectl, "kustomize", str(root / SETUPS[setup])],
                           capture_output=True, text=True, timeout=120)
        if r.returncode != 0:
            print(r.stderr)
            sys.exit(1)
        rendered = load_yaml_all(r.stdout)
        check_manifests(rendered, setup, problems)
        # The renderer behind `manifests` must agree with kustomize itself.
        ours = render_kustomization(root / SETUPS[setup], problems)
        generated_names = [d["metadata"]["name"] for d in ours
                           if d.get("kind") in ("ConfigMap", "Secret")]
        mine, theirs = canonical(ours, generated_names), canonical(rendered, generated_names)
        for doc in sorted(set(mine) ^ set(theirs)):
            problems.append(("only check_deploy.py renders " if doc in mine else
                             "only kubectl renders ") + doc[:300])
    elif what == "compose":
        check_compose(root, sys.argv[3], problems)
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
