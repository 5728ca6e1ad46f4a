"""Parameter sweeps and ensembles of collisionkit runs, as library calls.

A *study* names a command (``edmd``, ``swarm``, ``slab``, ``encounter``),
its fixed parameters, the parameters to vary and the number of replicas::

    command = "edmd"
    replicas = 2
    seed = 1
    [fixed]
    dim = 3
    particles = 500
    collisions = 20000
    [vary]
    packing-fraction = [0.1, 0.2, 0.3]              # a list
    # restitution = {start = 0.8, stop = 1.0, num = 3}   # num values, both ends included
    # particles = {start = 100, stop = 400, step = 100}  # start, start + step, ... <= stop
    # zip = [["a", "b"]] at the top level varies a and b together instead of crosswise

Option names are the command-line flags (``packing-fraction``, ``E-N``);
the Python parameter names (``packing_fraction``, ``reduced_field``) are
accepted too. The points are the cartesian product of the varied options
(keys of a ``zip`` group advance together). Every point is checked by the
command's own rules before any runs. Each point and replica runs the
command's library call (never the command line) in its own folder
``OUT/points/pNNNN-rNN``, with its own seed from
:class:`numpy.random.SeedSequence` (spawn key ``(point, replica)`` under the
study's root seed), so the numbers do not depend on the number of workers
or the order of execution.

Each point's ``result.json`` and ``summary.json`` are written atomically as
soon as it finishes; the study's checkpoint ``OUT/checkpoint.npz`` lets
:func:`resume_study` skip the finished points and rerun the others
(``run_study(..., overwrite=True)`` starts the study in a folder again,
removing only the files a sweep wrote there). At the
end the study folder gets ``results.csv`` (one row per point and replica;
nested results as ``a.b``, vectors as ``v[i]``), ``results.parquet`` when
``pyarrow`` is installed, and ``main_result.png`` (the main result against
the first varied option, the replicas combined) when matplotlib is.

Points run on any :class:`concurrent.futures.Executor` or on a
``dask.distributed.Client``; by default on an embedded ``LocalCluster``
(``pip install 'collisionkit[cluster]'``).
"""

from .clients import local_client, remote_client
from .commands import MAIN_RESULTS, SweepCommand, sweep_command, sweep_commands
from .execute import (
    OutputsNotWritten, StudyResults, check_folder, resume_study, run_point, run_study,
)
from .study import Study, expand, load_study, study_from_dict
from .statistics import combine_replicas
from .table import aggregate, group_key, points_table, results_table, write_csv, write_outputs, write_parquet
from .tasks import PointTask, check_command, point_name, point_seed, point_tasks

__all__ = [
    "MAIN_RESULTS",
    "PointTask",
    "Study",
    "OutputsNotWritten",
    "StudyResults",
    "SweepCommand",
    "aggregate",
    "group_key",
    "check_command",
    "check_folder",
    "combine_replicas",
    "expand",
    "load_study",
    "local_client",
    "point_name",
    "point_seed",
    "point_tasks",
    "points_table",
    "remote_client",
    "results_table",
    "resume_study",
    "run_point",
    "run_study",
    "study_from_dict",
    "sweep_command",
    "sweep_commands",
    "write_csv",
    "write_outputs",
    "write_parquet",
]
