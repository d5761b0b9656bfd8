# SPDX-License-Identifier: GPL-3.0-or-later
"""A throwaway one-node Slurm cluster on this machine: to try the farm commands of the README,
and for the Slurm test and benchmark.  Standard library only.

    phong cluster start DIR   # prints DIR/slurm.conf: export SLURM_CONF=$(...)
    phong cluster stop DIR    # cancels its jobs, stops its daemons

It needs root (the daemons and the jobs run as root) and Debian's packages ``slurmctld
slurmd slurm-client munge`` (Slurm 22.05 on Debian 12).  Everything lives in DIR: its own
MUNGE key and socket (``/etc/munge`` is not used), ``slurm.conf``, state, spool, logs and the
daemons' pids; the ports are free ones picked at start, so it runs beside another cluster.
The daemons (munged, slurmctld, slurmd) are started directly, without systemd:
``proctrack/linuxproc`` and ``task/none`` need no cgroups; ``select/cons_tres`` with
``CR_Core`` runs one task per core.  ``cred_expire=5`` and ``sched_interval=1`` let a
requeued task start again after about 6 s (Slurm's defaults wait 120 s, then up to 60 s).
"""

from __future__ import annotations

import json
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import time

from . import system

SBIN = os.pathsep.join([os.environ.get("PATH", ""), "/usr/sbin", "/sbin"])
DAEMONS = ("munged", "slurmctld", "slurmd")


class ClusterError(Exception):
    """The cluster could not start (one line, with the end of the daemon's log)."""


def unavailable() -> str | None:
    """Why no one-node cluster can start here (what to do about it), or None."""
    if not sys.platform.startswith("linux"):
        return "a one-node Slurm cluster needs Linux"
    packages = system.cluster_packages()
    if packages:
        return ("a one-node Slurm cluster needs Debian's Slurm and MUNGE: "
                f"apt-get install -y {' '.join(packages)} (as root)")
    if os.geteuid() != 0:
        return "a one-node Slurm cluster runs its daemons and jobs as root: run as root"
    return None


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _memory_mb() -> int:
    try:
        with open("/proc/meminfo", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) * 9 // 10 // 1024
    except (OSError, ValueError, IndexError):
        pass
    return 1024


def _alive(pid: int) -> bool:
    """True while *pid* runs (a zombie counts as gone)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as handle:
            return handle.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def _command_of(pid: int) -> str:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as handle:
            return handle.read().split(b"\0")[0].decode(errors="replace")
    except OSError:
        return ""


class Cluster:
    """The one-node cluster whose files live in *folder*."""

    def __init__(self, folder: str):
        self.folder = os.path.abspath(folder)
        self.conf = os.path.join(self.folder, "slurm.conf")
        self.env = dict(os.environ, SLURM_CONF=self.conf)
        self._children = {}

    def path(self, *parts) -> str:
        return os.path.join(self.folder, *parts)

    # -- start ----------------------------------------------------------------------

    def start(self, timeout: float = 60.0) -> None:
        """Start munged, slurmctld and slurmd; return when the node is idle (ClusterError
        otherwise, with every daemon stopped again)."""
        problem = unavailable()
        if problem:
            raise ClusterError(problem)
        if self.running():
            raise ClusterError(f"a cluster of {self.folder} is already running")
        for sub in ("munge", "state", "spool"):
            os.makedirs(self.path(sub), exist_ok=True)
        os.chmod(self.folder, 0o755)
        os.chmod(self.path("munge"), 0o755)  # munged wants its socket's folder searchable
        key = self.path("munge", "munge.key")
        with open(os.open(key, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), "wb") as handle:
            handle.write(secrets.token_bytes(128))
        self._write_conf()
        try:
            self._spawn("munged", [shutil.which("munged", path=SBIN), "--foreground", "--force",
                                   f"--socket={self.path('munge', 'socket')}",
                                   f"--key-file={key}", f"--log-file={self.path('munged.log')}",
                                   f"--pid-file={self.path('munge', 'munged.pid')}",
                                   f"--seed-file={self.path('munge', 'seed')}"])
            self._wait(lambda: os.path.exists(self.path("munge", "socket")), 10, "munged")
            self._spawn("slurmctld", [shutil.which("slurmctld", path=SBIN), "-D", "-f",
                                      self.conf])
            self._spawn("slurmd", [shutil.which("slurmd", path=SBIN), "-D", "-f", self.conf])
            self._wait(self._idle, timeout, "slurmd")
        except BaseException:
            self.stop()
            raise

    def _write_conf(self) -> None:
        host = socket.gethostname().split(".")[0]
        lines = [
            "# A one-node cluster written by phong cluster (cli/cluster.py)",
            "ClusterName=phong",
            f"SlurmctldHost={host}(127.0.0.1)",
            f"SlurmctldPort={_free_port()}",
            f"SlurmdPort={_free_port()}",
            "SlurmUser=root",
            "SlurmdUser=root",
            "AuthType=auth/munge",
            "CredType=cred/munge",
            f"AuthInfo=socket={self.path('munge', 'socket')},cred_expire=5",
            f"StateSaveLocation={self.path('state')}",
            f"SlurmdSpoolDir={self.path('spool')}",
            f"SlurmctldPidFile={self.path('slurmctld.pid')}",
            f"SlurmdPidFile={self.path('slurmd.pid')}",
            f"SlurmctldLogFile={self.path('slurmctld.log')}",
            f"SlurmdLogFile={self.path('slurmd.log')}",
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "SwitchType=switch/none",
            "MpiDefault=none",
            "JobAcctGatherType=jobacct_gather/none",
            "AccountingStorageType=accounting_storage/none",
            "SchedulerType=sched/builtin",
            "SchedulerParameters=sched_interval=1",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_Core",
            "ReturnToService=2",
            "KillWait=5",
            "MinJobAge=600",
            f"NodeName={host} NodeAddr=127.0.0.1 CPUs={os.cpu_count() or 1} "
            f"RealMemory={_memory_mb()} State=UNKNOWN",
            "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP",
        ]
        with open(self.conf, "w", encoding="ascii") as handle:
            handle.write("\n".join(lines) + "\n")

    def _spawn(self, name: str, command: list) -> None:
        log = open(self.path(f"{name}.out"), "ab")  # noqa: SIM115  (the daemon keeps it)
        child = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log,
                                 stderr=subprocess.STDOUT, env=self.env,
                                 start_new_session=True)
        log.close()
        self._children[name] = child
        pids = self._pids()
        pids[name] = child.pid
        with open(self.path("pids.json"), "w", encoding="ascii") as handle:
            json.dump(pids, handle)

    def _idle(self) -> bool:
        state = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True,
                               env=self.env, check=False)
        return state.returncode == 0 and state.stdout.strip() in ("idle", "mixed")

    def _wait(self, ready, timeout: float, name: str) -> None:
        end = time.monotonic() + timeout
        while not ready():
            dead = [n for n, child in self._children.items() if child.poll() is not None]
            if dead or time.monotonic() > end:
                what = dead[0] if dead else name
                raise ClusterError(f"{what} {'exited' if dead else 'did not get ready'}: "
                                   f"{self._log_tail(what)}")
            time.sleep(0.2)

    def _log_tail(self, name: str) -> str:
        text = ""
        for log in (self.path(f"{name}.log"), self.path(f"{name}.out")):
            if os.path.exists(log):
                with open(log, encoding="utf-8", errors="replace") as handle:
                    text += handle.read()
        lines = [l.strip() for l in text.splitlines() if l.strip()]
        return " | ".join(lines[-3:]) or f"no log in {self.folder}"

    # -- use --------------------------------------------------------------------------

    def run(self, *command, check: bool = True, **kwargs) -> subprocess.CompletedProcess:
        """A Slurm command (sbatch, squeue, scontrol...) against this cluster."""
        return subprocess.run(list(command), capture_output=True, text=True, env=self.env,
                              check=check, **kwargs)

    def jobs(self) -> list:
        """Ids of the jobs the cluster still holds pending or running."""
        out = self.run("squeue", "-h", "-o", "%i", check=False).stdout
        return [line.strip() for line in out.splitlines() if line.strip()]

    # -- stop ---------------------------------------------------------------------------

    def _pids(self) -> dict:
        try:
            with open(self.path("pids.json"), encoding="ascii") as handle:
                return {k: int(v) for k, v in json.load(handle).items()}
        except (OSError, ValueError, AttributeError):
            return {}

    def running(self) -> list:
        """The daemons of this folder that still run."""
        return [name for name, pid in self._pids().items()
                if _alive(pid) and os.path.basename(_command_of(pid)) == name]

    def stop(self, timeout: float = 30.0) -> None:
        """Cancel every job, then stop slurmd, slurmctld and munged (SIGTERM, SIGKILL after
        *timeout* s); nothing of this cluster runs afterwards."""
        if "slurmctld" in self.running():
            ids = self.jobs()
            if ids:
                self.run("scancel", *ids, check=False)
                end = time.monotonic() + timeout
                while self.jobs() and time.monotonic() < end:
                    time.sleep(0.3)
        pids = self._pids()
        for name in reversed(DAEMONS):
            pid = pids.get(name)
            if pid is None or name not in self.running():
                continue
            os.kill(pid, signal.SIGTERM)
            end = time.monotonic() + timeout
            while _alive(pid) and time.monotonic() < end:
                time.sleep(0.1)
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
        for child in self._children.values():
            try:
                child.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                child.kill()
                child.wait()
        self._children.clear()


def main(argv) -> int:
    if len(argv) != 2 or argv[0] not in ("start", "stop"):
        print("usage: phong cluster start|stop DIR", file=sys.stderr)
        return 2
    cluster = Cluster(argv[1])
    if argv[0] == "stop":
        cluster.stop()
        return 0
    try:
        cluster.start()
    except ClusterError as error:
        print(f"cluster: {error}", file=sys.stderr)
        return 1
    print(cluster.conf)
    return 0

