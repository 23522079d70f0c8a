#!/usr/bin/env python3
"""The durable job store with the real binaries: depathd on SQLite (its default) and on a real
PostgreSQL started here (initdb/pg_ctl as user postgres in a temporary directory), driven by the
`depath` client as a user would.

Checked: after kill -9 and after SIGTERM every job is listed, a finished result is fetchable, a
running job resumes from its checkpoint and ends bit-identical (points and energy) to an
uninterrupted in-process `depath solve`, a queued job runs, a watcher resuming with --after misses
nothing; two replicas share PostgreSQL (takeover after kill -9, cancel across replicas, 50 jobs
neither lost nor completed twice); TTL clean-up leaves no rows behind; clear errors for an
unreachable store, a newer schema and a second server on one SQLite file.

Liveness bounds are derived from the configured limits and scaled by DEPATH_TEST_TIME_SCALE."""
import argparse
import glob
import json
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time

SCALE = float(os.environ.get("DEPATH_TEST_TIME_SCALE", "1"))
# Generations of the job that gets interrupted (at generation >= 400): shorter under sanitizers.
LONG = 2500 if SCALE <= 1 else 900
ARGS = None
WORK = None


def check(cond, message):
    if not cond:
        raise AssertionError(message)


def spec(seed, generations):
    return ["-s", "0", "-t", "1400", "--population", "16", "--generations", str(generations), "--strategy", "shade",
            "--seed", str(seed)]


def client(*args, timeout=120):
    return subprocess.run([ARGS.depath] + list(args), capture_output=True, text=True, timeout=timeout * SCALE)


_refs = {}


def reference(seed, generations):
    """The uninterrupted in-process result."""
    key = (seed, generations)
    if key not in _refs:
        out = os.path.join(WORK, "ref-%d-%d.json" % key)
        r = client("solve", ARGS.mesh, *spec(seed, generations), "--threads", "2", "--out", out, timeout=600)
        check(r.returncode == 0, "solve failed: " + r.stderr[-300:])
        _refs[key] = json.load(open(out))
    return _refs[key]


class Daemon:
    count = 0

    def __init__(self, store_args, extra=(), port=0):
        Daemon.count += 1
        self.name = "d%d" % Daemon.count
        self.port_file = os.path.join(WORK, self.name + ".port")
        self.log_path = os.path.join(WORK, self.name + ".log")
        self.proc = subprocess.Popen([ARGS.depathd, "--listen", "127.0.0.1:%d" % port, "--port-file", self.port_file,
                                      "--threads", "2", "--log-format", "json", "--log-level", "debug"]
                                     + list(store_args) + list(extra),
                                     stdout=subprocess.DEVNULL, stderr=open(self.log_path, "w"))
        deadline = time.monotonic() + 30 * SCALE
        while not (os.path.exists(self.port_file) and open(self.port_file).read().strip()):
            check(self.proc.poll() is None, "depathd exited at start: " + open(self.log_path).read()[-400:])
            check(time.monotonic() < deadline, "depathd did not start")
            time.sleep(0.02)
        self.address = "127.0.0.1:" + open(self.port_file).read().strip()

    def stop(self, sig=signal.SIGTERM):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            self.proc.wait(timeout=60 * SCALE)
        return self.proc.returncode

    def log_lines(self, message):
        out = []
        for line in open(self.log_path):
            try:
                entry = json.loads(line)
            except ValueError:
                continue
            if entry.get("msg") == message or entry.get("message") == message or entry.get("event") == message:
                out.append(entry)
        return out


def wait_checkpoint(d, job, generation):
    """Until the daemon's log says a checkpoint at `generation` or later is stored (they are
    written beside the run, so a slow disk can lag behind the generations watchers see)."""
    deadline = time.monotonic() + 60 * SCALE
    while not any(e.get("job") == job and e.get("generation", 0) >= generation for e in d.log_lines("job.checkpointed")):
        check(time.monotonic() < deadline, "no checkpoint at generation >= %d stored" % generation)
        time.sleep(0.05)


def journaled_after(d, job, generation):
    """The generations after `generation` the daemon's log says are in the job's journal."""
    out = set()
    for e in d.log_lines("job.journaled"):
        if e.get("job") == job:
            out.update(g for g in range(e["first_generation"], e["last_generation"] + 1) if g > generation)
    return out


def wait_journal_past_checkpoint(d, job):
    """Until a journal write covers a generation after the latest stored checkpoint."""
    deadline = time.monotonic() + 60 * SCALE
    while True:
        latest = max((e.get("generation", 0) for e in d.log_lines("job.checkpointed") if e.get("job") == job), default=0)
        if journaled_after(d, job, latest):
            return
        check(time.monotonic() < deadline, "no journal past the checkpoint at generation %d" % latest)
        time.sleep(0.02)


def submit(d, seed, generations):
    r = client("submit", ARGS.mesh, *spec(seed, generations), "--server", d.address)
    check(r.returncode == 0 and r.stdout.strip().startswith("job-"), "submit failed: %s %s" % (r.stdout, r.stderr))
    return r.stdout.strip()


def watch_until_generation(d, job, generation):
    """Follows the job's JSON events until `generation`; returns the last sequence seen."""
    w = subprocess.Popen([ARGS.depath, "watch", job, "--json", "--server", d.address], stdout=subprocess.PIPE,
                         text=True)
    seq, gen = 0, 0
    try:
        for line in w.stdout:
            e = json.loads(line)
            seq = max(seq, e.get("sequence", 0))
            gen = e.get("generation", gen)
            if gen >= generation:
                break
    finally:
        w.kill()
        w.wait()
    check(gen >= generation, "job %s ended before generation %d" % (job, generation))
    return seq


def events(d, job, after=0, timeout=300, codes=(0,)):
    """The job's events until it ends; `depath watch` exits 0 only when it succeeded."""
    r = client("watch", job, "--json", "--after", str(after), "--server", d.address, timeout=timeout)
    check(r.returncode in codes, "watch %s failed (rc %d): %s" % (job, r.returncode, r.stderr[-300:]))
    return [json.loads(l) for l in r.stdout.splitlines() if l.strip()]


def final_state(evs):
    states = [e.get("state") for e in evs if e.get("event") == "state"]
    return states[-1] if states else None


def result(d, job):
    out = os.path.join(WORK, job + ".json")
    r = client("result", job, "--out", out, "--server", d.address)
    check(r.returncode == 0, "result %s: %s" % (job, r.stderr[-300:]))
    return json.load(open(out))


def same(got, ref):
    return got["points"] == ref["points"] and got["energy"] == ref["energy"]


def restart_durability(store_args, label):
    """kill -9 and SIGTERM mid-job, then a restart on the same store."""
    for sig in (signal.SIGKILL, signal.SIGTERM):
        d = Daemon(store_args, ["--checkpoint-seconds", "0.3", "--max-running-jobs", "1"])
        short = submit(d, 2, 20)
        check(final_state(events(d, short)) == "succeeded", "short job did not succeed")
        long_job = submit(d, 3, LONG)
        queued = submit(d, 4, 150)
        seen = watch_until_generation(d, long_job, 400)
        wait_checkpoint(d, long_job, 300)
        if sig == signal.SIGKILL:
            wait_journal_past_checkpoint(d, long_job)
        d.stop(sig)
        before = d
        t0 = time.monotonic()
        d = Daemon(store_args, ["--checkpoint-seconds", "0.3", "--max-running-jobs", "1"])
        try:
            listed = client("jobs", "--server", d.address)
            for job in (short, long_job, queued):
                check(job in listed.stdout, "%s: %s not listed after restart" % (sig.name, job))
            check(same(result(d, short), reference(2, 20)), "short job's result changed across the restart")
            after = events(d, long_job, after=seen)
            check(all(e["sequence"] > seen for e in after if "sequence" in e), "watch --after %d sent older events" % seen)
            states = [e.get("state") for e in after if e.get("event") == "state"]
            check(states and states[-1] == "succeeded", "%s: states after restart %s" % (sig.name, states))
            check(sum(1 for e in after if e.get("event") == "result") == 1, "no single result event after resume")
            took = time.monotonic() - t0
            got = result(d, long_job)
            check(same(got, reference(3, LONG)), "%s on %s: resumed result differs (%.12g vs %.12g)"
                  % (sig.name, label, got["energy"], reference(3, LONG)["energy"]))
            resumed = d.log_lines("job.resumed")
            check(any(e.get("job") == long_job and e.get("checkpoint_generation", -1) >= 300 for e in resumed),
                  "%s: the job did not resume from a checkpoint at generation >= 300: %s" % (sig.name, resumed))
            # The journal since that checkpoint came back whole (what the log says was stored,
            # perhaps more: a write can land just before the kill without its log line); a
            # suspend checkpoints the generation it stops at, so nothing follows it.
            mine = [e for e in resumed if e.get("job") == long_job][0]
            stored = journaled_after(before, long_job, mine["checkpoint_generation"])
            if sig == signal.SIGKILL:
                check(mine.get("journal_generations", -1) >= len(stored),
                      "%s: resumed with %s journal generations, %d were stored" % (sig.name, mine.get("journal_generations"), len(stored)))
            else:
                check(mine.get("journal_generations") == 0, "SIGTERM: resumed with a journal: %s" % mine)
            check(final_state(events(d, queued)) == "succeeded", "queued job did not run after restart")
            check(same(result(d, queued), reference(4, 150)), "queued job's result differs")
            print("%s %s: resumed from generation %s with %s generations of journal, identical result, finished %.1f s after restart"
                  % (label, sig.name, mine["checkpoint_generation"], mine.get("journal_generations"), took))
        finally:
            d.stop()


def test_sqlite():
    data = os.path.join(WORK, "data")
    restart_durability(["--data-dir", data], "sqlite")
    check(os.path.exists(os.path.join(data, "depath.db")), "no depath.db in --data-dir")
    # One writer: a second server on the same data directory is refused with a clear message.
    first = Daemon(["--data-dir", data])
    try:
        r = subprocess.run([ARGS.depathd, "--listen", "127.0.0.1:0", "--data-dir", data], capture_output=True,
                           text=True, timeout=30 * SCALE)
        check(r.returncode == 2 and "in use by another depathd" in r.stderr, "second server: " + r.stderr)
    finally:
        first.stop()


def test_run_rides_through_restart():
    """`depath run` keeps going while its server is killed (kill -9) and restarted on the same
    address and data dir: it says it is reconnecting, then ends with the resumed job's result,
    identical to an uninterrupted solve."""
    data = os.path.join(WORK, "ride")
    opts = ["--checkpoint-seconds", "0.3", "--max-running-jobs", "1"]
    d = Daemon(["--data-dir", data], opts)
    port = int(d.address.rsplit(":", 1)[1])
    out = os.path.join(WORK, "ride.json")
    run = subprocess.Popen([ARGS.depath, "run", ARGS.mesh, *spec(3, LONG), "--out", out, "--server", d.address],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60 * SCALE
        while not d.log_lines("job.started"):
            check(time.monotonic() < deadline and run.poll() is None, "the run's job did not start")
            time.sleep(0.05)
        job = d.log_lines("job.started")[0]["job"]
        wait_checkpoint(d, job, 300)
        d.stop(signal.SIGKILL)
        d = Daemon(["--data-dir", data], opts, port=port)
        _, err = run.communicate(timeout=600 * SCALE)
        check(run.returncode == 0, "depath run did not ride through the restart (rc %d): %s" % (run.returncode, err[-400:]))
        check("reconnecting" in err, "no reconnecting note: " + err[-400:])
        check(same(json.load(open(out)), reference(3, LONG)), "the run's result differs from the uninterrupted one")
        print("sqlite: depath run rode through kill -9 and restart of its server, identical result")
    finally:
        if run.poll() is None:
            run.kill()
        d.stop()


def test_ttl_sqlite():
    data = os.path.join(WORK, "ttl")
    d = Daemon(["--data-dir", data], ["--job-ttl-seconds", "1"])
    try:
        job = submit(d, 2, 20)
        events(d, job)
        time.sleep(3 * SCALE)
        r = client("result", job, "--out", os.path.join(WORK, "x.json"), "--server", d.address)
        check(r.returncode != 0 and "expired" in r.stderr, "expired job: " + r.stderr)
        r = client("result", "job-0000000000000000", "--out", os.path.join(WORK, "x.json"), "--server", d.address)
        check(r.returncode != 0 and "not found" in r.stderr and "expired" not in r.stderr, "unknown job: " + r.stderr)
    finally:
        d.stop()
    db = sqlite3.connect(os.path.join(data, "depath.db"))
    for table in ("jobs", "events", "results", "checkpoints", "trial_journal"):
        rows = db.execute("SELECT COUNT(*) FROM %s" % table).fetchone()[0]
        check(rows == 0, "%d rows left in %s after the TTL" % (rows, table))


def refused(store):
    """depathd's exit status and message for --store STORE (a store it refuses exits at once)."""
    r = subprocess.run([ARGS.depathd, "--listen", "127.0.0.1:0", "--store", store], capture_output=True, text=True,
                       timeout=30 * SCALE)
    return r.returncode, r.stderr


def sqlite_file(name, *statements):
    path = os.path.join(WORK, name)
    db = sqlite3.connect(path)
    for sql in statements:
        db.execute(sql)
    db.commit()
    db.close()
    return path


def test_store_errors():
    code, err = refused("postgresql://postgres@127.0.0.1:1/x")
    check(code == 2 and "cannot connect to the PostgreSQL store" in err, "unreachable: " + err)
    newer = sqlite_file("newer.db", "CREATE TABLE schema_version (version BIGINT NOT NULL)",
                        "INSERT INTO schema_version VALUES (999)")
    code, err = refused("sqlite:" + newer)
    check(code == 2 and "newer than this depathd" in err, "newer schema: " + err)
    # A store is trusted by the names of its applied migrations, not by its version number.
    fresh = os.path.join(WORK, "fresh.db")
    d = Daemon(["--store", "sqlite:" + fresh])
    check(d.stop() == 0, "a fresh store: exit status %s" % d.proc.returncode)
    db = sqlite3.connect(fresh)
    names = [n for (n,) in db.execute("SELECT name FROM schema_migrations ORDER BY version")]
    version = db.execute("SELECT version FROM schema_version").fetchone()[0]
    check(len(names) == version and names[0] == "initial" and len(set(names)) == len(names),
          "recorded migrations %s at version %d" % (names, version))
    db.execute("UPDATE schema_migrations SET name = 'from_a_branch' WHERE version = 2")
    db.commit()
    db.close()
    code, err = refused("sqlite:" + fresh)
    check(code == 2 and 'schema migration 2 "from_a_branch" where this depathd has "%s"' % names[1] in err
          and "another build of depathd" in err, "a store migrated by another build: " + err)
    # Stores from before names were recorded go by their number; one whose schema is not what
    # the number says (a branch's migration 2 added what our 3 adds) is refused naming the step.
    legacy = sqlite_file("legacy.db", "CREATE TABLE jobs (number INTEGER PRIMARY KEY, id TEXT, state BIGINT, client TEXT)",
                         "CREATE TABLE schema_version (version BIGINT NOT NULL)",
                         "INSERT INTO schema_version VALUES (2)")
    code, err = refused("sqlite:" + legacy)
    check(code == 2 and 'schema migration 3 "%s" failed' % names[2] in err and "not what its version 2 says" in err,
          "a legacy store of another build: " + err)
    code, err = refused("mysql://x")
    check(code == 2 and "unknown --store" in err, "bad uri: " + err)


class Postgres:
    def __init__(self, bindir):
        self.bindir = bindir
        self.dir = tempfile.mkdtemp(prefix="depath_pg_")
        shutil.chown(self.dir, "postgres")
        self.port = 20000 + os.getpid() % 20000
        self.run("initdb", "-D", self.dir + "/data", "-A", "trust")
        self.run("pg_ctl", "-D", self.dir + "/data", "-o", "-p %d -k %s -h 127.0.0.1" % (self.port, self.dir),
                 "-l", self.dir + "/log", "-w", "start")
        self.dsn = "postgresql://postgres@127.0.0.1:%d/postgres" % self.port

    def run(self, tool, *args):
        r = subprocess.run(["runuser", "-u", "postgres", "--", os.path.join(self.bindir, tool)] + list(args),
                           capture_output=True, text=True, timeout=120)
        check(r.returncode == 0, "%s failed: %s" % (tool, r.stderr[-400:]))

    def query(self, sql):
        r = subprocess.run([os.path.join(self.bindir, "psql"), "-At", "-d", self.dsn, "-c", sql], capture_output=True,
                           text=True, timeout=60)
        check(r.returncode == 0, "psql: " + r.stderr)
        return r.stdout.strip()

    def stop(self):
        subprocess.run(["runuser", "-u", "postgres", "--", os.path.join(self.bindir, "pg_ctl"), "-D",
                        self.dir + "/data", "-m", "fast", "stop"], capture_output=True, timeout=120)
        shutil.rmtree(self.dir, ignore_errors=True)


def runner_of(daemons, job):
    """The replica whose log says it started or resumed the job last."""
    found = None
    for d in daemons:
        for e in d.log_lines("job.started") + d.log_lines("job.resumed"):
            if e.get("job") == job:
                found = d
    return found


def multi_address_target(a, b):
    """Any client call through one target naming both replicas (as a dns:/// name with two A
    records would): calls spread over the replicas and each finds what another stored."""
    multi = "ipv4:%s,%s" % (a.address, b.address)
    ref = reference(7, 15)
    for k in range(3):
        out = os.path.join(WORK, "multi-run-%d.json" % k)
        r = client("run", ARGS.mesh, *spec(7, 15), "--out", out, "--server", multi)
        check(r.returncode == 0, "run through both replicas: " + r.stderr[-300:])
        check(same(json.load(open(out)), ref), "run through both replicas differs from the in-process solve")
    jobs = []
    for k in range(4):
        r = client("submit", ARGS.mesh, *spec(7, 15), "--server", multi)
        check(r.returncode == 0, "submit through both replicas: " + r.stderr[-300:])
        jobs.append(r.stdout.strip())
    for job in jobs:
        r = client("watch", job, "--json", "--server", multi)
        check(r.returncode == 0, "watch %s through both replicas: %s" % (job, r.stderr[-300:]))
        out = os.path.join(WORK, job + "-multi.json")
        r = client("result", job, "--out", out, "--server", multi)
        check(r.returncode == 0 and same(json.load(open(out)), ref), "result %s through both replicas" % job)
    r = client("jobs", "--json", "--server", multi)
    listed = [json.loads(l)["job_id"] for l in r.stdout.splitlines() if l.strip()]
    check(r.returncode == 0 and all(listed.count(j) == 1 for j in jobs), "jobs through both replicas: %s" % r.stderr)
    victim = submit(b, 8, 100000)
    r = client("cancel", victim, "--server", multi)
    check(r.returncode == 0, "cancel through both replicas: " + r.stderr)
    check(final_state(events(a, victim, timeout=30, codes=(130,))) == "cancelled", "not cancelled")
    r = client("result", "job-unknown", "--server", multi)
    check(r.returncode == 2 and "NOT_FOUND" in r.stderr, "unknown job through both replicas: " + r.stderr)
    print("postgresql: run/submit/watch/result/jobs/cancel through one target naming both replicas: ok")


def named_replica_restart(pg):
    """A replica with a stable --replica-id killed mid-job takes the job back when it restarts,
    long before its lease (600 s here) would have let anyone else, and the result is identical."""
    opts = ["--store", pg.dsn, "--replica-id", "replica-one", "--lease-seconds", "600", "--checkpoint-seconds", "0.3",
            "--max-running-jobs", "1"]
    d = Daemon(opts)
    job = submit(d, 3, LONG)
    watch_until_generation(d, job, 300)
    wait_checkpoint(d, job, 300)
    d.stop(signal.SIGKILL)
    d = Daemon(opts)
    try:
        t0 = time.monotonic()
        events(d, job, timeout=600)
        check(same(result(d, job), reference(3, LONG)), "named replica's resumed result differs")
        released = d.log_lines("jobs.released")
        check(released and released[0].get("count", 0) >= 1, "the restarted replica did not release its old leases")
        print("postgresql: named replica restarted after kill -9 took its job back (lease 600 s) and finished it "
              "%.1f s later, identical" % (time.monotonic() - t0))
    finally:
        d.stop()


def client_quota_across_replicas(pg):
    """--max-jobs-per-client counts the client's queued + running jobs in the shared store: one
    client (a token) hitting both replicas gets at most the cap in all; another token is not held
    back by it; a finished job frees a place on either replica."""
    store = ["--store", pg.dsn]
    opts = ["--max-jobs-per-client", "2", "--max-running-jobs", "1", "--auth-token", "alice", "--auth-token", "bob"]
    a, b = Daemon(store, opts), Daemon(store, opts)
    try:
        def as_client(token, d, seed):
            return client("submit", ARGS.mesh, *spec(seed, 100000), "--server", d.address, "--token", token)

        first, second = as_client("alice", a, 1), as_client("alice", b, 2)
        check(first.returncode == 0 and second.returncode == 0, "alice's first two jobs: " + first.stderr + second.stderr)
        for d in (a, b):
            r = as_client("alice", d, 3)
            check(r.returncode != 0 and "RESOURCE_EXHAUSTED" in r.stderr and "--max-jobs-per-client 2" in r.stderr
                  and "already has 2 jobs" in r.stderr, "alice's third job on %s: %s" % (d.name, r.stderr))
        other = as_client("bob", b, 4)
        check(other.returncode == 0, "bob is not held back by alice's jobs: " + other.stderr)
        r = client("cancel", first.stdout.strip(), "--server", b.address, "--token", "alice")
        check(r.returncode == 0, "cancel: " + r.stderr)
        w = client("watch", first.stdout.strip(), "--json", "--server", a.address, "--token", "alice", timeout=30)
        evs = [json.loads(l) for l in w.stdout.splitlines() if l.strip()]
        check(final_state(evs) == "cancelled", "not cancelled: %s %s" % (final_state(evs), w.stderr[-200:]))
        again = as_client("alice", a, 5)
        check(again.returncode == 0, "alice after one of her jobs ended: " + again.stderr)
        for r in (second, other, again):
            client("cancel", r.stdout.strip(), "--server", a.address, "--token", "alice")
        print("postgresql: --max-jobs-per-client 2 held across 2 replicas (third job refused on both; "
              "another client unaffected; a cancelled job freed a place)")
    finally:
        a.stop()
        b.stop()


def test_postgres(pg):
    restart_durability(["--store", pg.dsn], "postgresql")
    named_replica_restart(pg)
    store = ["--store", pg.dsn]
    opts = ["--lease-seconds", "2", "--checkpoint-seconds", "0.3", "--max-running-jobs", "1"]
    a = Daemon(store, opts)
    b = None
    try:
        # Takeover: the replica running a job dies; the other resumes it from its checkpoint.
        job = submit(a, 3, LONG)
        watch_until_generation(a, job, 300)
        b = Daemon(store, opts)
        watch_until_generation(b, job, 400)  # live progress through the other replica
        wait_checkpoint(a, job, 300)
        wait_journal_past_checkpoint(a, job)
        a.stop(signal.SIGKILL)
        t0 = time.monotonic()
        evs = events(b, job, timeout=600)
        check(same(result(b, job), reference(3, LONG)), "taken-over result differs from the uninterrupted one")
        check(sum(1 for e in evs if e.get("event") == "result") == 1, "the job completed more than once")
        check([e.get("state") for e in evs if e.get("event") == "state"].count("succeeded") == 1, "two terminal events")
        resumed = [e for e in b.log_lines("job.resumed") if e.get("job") == job]
        check(resumed and resumed[0].get("checkpoint_generation", -1) >= 300, "B did not resume from a checkpoint")
        stored = journaled_after(a, job, resumed[0]["checkpoint_generation"])
        check(resumed[0].get("journal_generations", -1) >= len(stored),
              "B resumed with %s journal generations, A stored %d" % (resumed[0].get("journal_generations"), len(stored)))
        print("postgresql takeover after kill -9: resumed on the other replica from generation %d with %d generations "
              "of journal, identical, done %.1f s later"
              % (resumed[0]["checkpoint_generation"], resumed[0]["journal_generations"], time.monotonic() - t0))
        # Its progress history has no gap (the checkpoint carries the generations before it; the
        # resumed run repeats those after it), thinned past 1000 points as store/job_store.hpp says.
        g_end = result(b, job)["generations"]
        stride = 1
        while g_end // stride >= 1000:
            stride *= 2
        stored = pg.query("SELECT string_agg(generation::text, ',' ORDER BY generation) FROM progress_history "
                          "WHERE job_id = '%s'" % job)
        expected = sorted({1, g_end} | set(range(stride, g_end + 1, stride)))
        check(stored == ",".join(map(str, expected)),
              "history of the taken-over job: %s..., expected %d points, stride %d" % (stored[:60], len(expected), stride))
        rises = pg.query("SELECT COUNT(*) FROM (SELECT best_energy, LAG(best_energy) OVER (ORDER BY generation) AS prev "
                         "FROM progress_history WHERE job_id = '%s') h WHERE best_energy > prev" % job)
        check(rises == "0", "the best energy rises %s times in the history" % rises)
        print("postgresql: the taken-over job's history has its %d points (stride %d)" % (len(expected), stride))

        # Cancel through the replica that does not run the job.
        a = Daemon(store, opts)
        victim = submit(b, 5, 100000)
        deadline = time.monotonic() + 30 * SCALE
        while runner_of([a, b], victim) is None:
            check(time.monotonic() < deadline, "nobody runs the job")
            time.sleep(0.05)
        other = a if runner_of([a, b], victim) is b else b
        t1 = time.monotonic()
        r = client("cancel", victim, "--server", other.address)
        check(r.returncode == 0, "cancel: " + r.stderr)
        evs = events(other, victim, timeout=30, codes=(130,))
        took = time.monotonic() - t1
        check(final_state(evs) == "cancelled", "not cancelled: %s" % final_state(evs))
        check(took < 10 * SCALE, "cancel across replicas took %.1f s" % took)
        print("postgresql cancel through the other replica: %.2f s" % took)

        # 50 jobs over 2 replicas: none lost, none completed twice.
        jobs = [submit(a if k % 2 else b, 100 + k, 15) for k in range(50)]
        t2 = time.monotonic()
        for job in jobs:
            evs = events(a, job)
            check([e.get("state") for e in evs if e.get("event") == "state"].count("succeeded") == 1,
                  "job %s: %s" % (job, [e.get("state") for e in evs]))
        finished = [e["job"] for d in (a, b) for e in d.log_lines("job.finished")]
        for job in jobs:
            check(finished.count(job) == 1, "job %s finished %d times" % (job, finished.count(job)))
        print("postgresql: 50 jobs over 2 replicas in %.1f s, each finished exactly once (%d on A, %d on B)"
              % (time.monotonic() - t2, sum(1 for e in a.log_lines("job.finished") if e["job"] in jobs),
                 sum(1 for e in b.log_lines("job.finished") if e["job"] in jobs)))

        multi_address_target(a, b)
    finally:
        for d in (a, b):
            if d:
                d.stop()
    client_quota_across_replicas(pg)
    # TTL clean-up on PostgreSQL.
    d = Daemon(store, ["--job-ttl-seconds", "1"])
    try:
        time.sleep(3 * SCALE)
        for table in ("jobs", "events", "results", "checkpoints", "progress_history", "trial_journal"):
            check(pg.query("SELECT COUNT(*) FROM %s" % table) == "0", "rows left in %s after the TTL" % table)
        check(int(pg.query("SELECT COUNT(*) FROM expired_jobs")) >= 50, "no tombstones for expired jobs")
    finally:
        d.stop()


def main():
    global ARGS, WORK
    ap = argparse.ArgumentParser()
    ap.add_argument("--depathd", required=True)
    ap.add_argument("--depath", required=True)
    ap.add_argument("--mesh", required=True)
    ARGS = ap.parse_args()
    WORK = tempfile.mkdtemp(prefix="depath_store_")
    try:
        test_store_errors()
        test_ttl_sqlite()
        test_sqlite()
        test_run_rides_through_restart()
        bindir = sorted(glob.glob("/usr/lib/postgresql/*/bin"))
        if not bindir or not os.path.exists(os.path.join(bindir[-1], "initdb")):
            print("SKIPPED the PostgreSQL part: no PostgreSQL server binaries (Debian package postgresql)")
            return 0
        pg = Postgres(bindir[-1])
        try:
            test_postgres(pg)
        finally:
            pg.stop()
    finally:
        shutil.rmtree(WORK, ignore_errors=True)
    print("store tests passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
