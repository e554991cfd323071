"""Shared by the serial-vs-MPI comparisons: runs a parameter file on 1 and on 2 ranks."""
import os
import subprocess


def run_serial_and_np2(nlmech, prm, work):
    """Runs `prm` serially and under `mpirun -np 2`, each into its own folder below `work`.

    Returns {1: folder, 2: folder}, or None after printing the output of a run that failed.
    """
    folders = {}
    for ranks in (1, 2):
        out = os.path.join(work, f"np{ranks}")
        prefix = [] if ranks == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2"]
        run = subprocess.run(prefix + [nlmech, prm, "--output-directory", out], capture_output=True, text=True)
        if run.returncode != 0:
            print(run.stdout, run.stderr)
            print(f"FAIL: run on {ranks} rank(s) exited with {run.returncode}")
            return None
        folders[ranks] = out
    return folders
