"""What one run of the suite measures: sizes, models and repeat counts of each profile."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rasterkit import options

MODELS_DIR = Path(__file__).resolve().parents[2] / "shared" / "models"
"""The shared test models (``../shared/models`` beside the repository)."""

TARGET_SIZE = (1920, 1080)
"""The resolution at which the rasterization issue sets its targets."""

TARGET_MODELS = ("stanford-bunny", "ogre", "sportsCar")
"""The models whose 1920x1080 frames carry the render targets."""

MODES = options.MODES
"""The render modes timed: every one of :data:`rasterkit.options.MODES`."""


@dataclass(frozen=True)
class Settings:
    """One profile of the suite.

    Attributes
    ----------
    name : str
        ``full``, ``quick``, ``targets`` or ``tiny``.
    warmup, repeat : int
        Untimed runs first, then timed runs per side (the median is reported).
    models : tuple of str
        OBJ names (without ``.obj``) in :data:`MODELS_DIR`, small to large.
    sizes : tuple of (width, height)
        Render resolutions, pixels.
    fill_size : (width, height)
        Resolution of the fill-rate and thread scenes.
    fill_counts : tuple of int
        Triangle counts of the fill-rate scenes (depth complexity grows with the count).
    segments : int
        Number of random 2D segments.
    segment_size : (width, height)
        Image of the 2D line benchmark.
    cli_model : str
        Model rendered by the command-line benchmark.
    cli_size : (width, height)
    cold_runs : int
        First-ever CLI runs (each with an empty cache); 0 skips them.
    sweep_triangles : tuple of int
        Torus ring counts of the triangle-count sweep (2 * rings * rings / 2 triangles).
    sweep_sizes : tuple of (width, height)
        Resolutions of the pixel-count sweep.
    sweep_model : str
        Model of the pixel-count sweep.
    memory : tuple of str
        Workload families whose peak memory is measured (see :mod:`benchmarks.memory`).
    process_repeat : int
        Timed runs of the workloads that start a process per run (warm CLI runs).
    startup_model : str
        Model of the ``startup`` family's cold sequence and warm run, and of the
        ``contention`` family's frames.
    startup_size : (width, height)
        Their image size.
    demo_size : (width, height) or None
        Size of the cold ``rasterkit render --demo`` runs; None: the command's default.
    startup_cold_runs : int
        Repetitions of the cold measurements (each with new, empty Numba caches).
    startup_sequence : bool
        Whether the cold sequence (demo, then the model in every mode, one cache) runs;
        the cold demo alone always runs.
    first_model_runs : int
        Repetitions of the first renders of ten real models, each in an empty cache
        (``benchmarks/first_models.py``); 0 leaves them out.
    first_model_modes : tuple of str
        The modes of those first renders, each in its own empty cache (``--first-modes``).
    contention_processes : tuple of int
        How many rasterkit (and llvmpipe) processes render at once, one configuration each.
    contention_seconds : float
        Wall time each process renders frames for.
    aa_model : str
        Model of the ``aa`` family (``samples=4`` against 4x MSAA).
    aa_size : (width, height)
        Its image size.
    cv_model : str
        Model of the ``cv`` family (colour, depth, normals and ids against a plain frame).
    cv_size : (width, height)
        Its image size.
    svg_models : tuple of str
        Models of the ``svg`` family (hidden-line SVG, against fogleman/ln when built).
    svg_size : (width, height)
        Their drawing size.
    batch_size : (width, height)
        Image size of the ``batch`` family's folder renders.
    batch_models : tuple of str
        Its models (the medium ones, 50k-300k triangles, each 8 times).
    texture_models : tuple of str
        Models of the ``textures`` family (names of :data:`benchmarks.textured_models.MODELS`);
        the first is drawn in every variant (flat, bilinear, untextured), the others smooth
        and trilinear.
    texture_size : (width, height)
        Their image size, and that of the texture memory rows.
    textured_cold_runs : int
        Repetitions of the ``startup`` family's first textured render against the first
        untextured one (fuze, each in an empty cache; :mod:`benchmarks.first_textured`); 0
        leaves them out.
    lit_cold_runs : int
        Rounds of the ``startup`` family's first lit renders (phong, shadows, AO) against the
        first plain one (stanford-bunny, each in an empty cache; :mod:`benchmarks.first_lit`);
        0 leaves them out.
    lighting_models : tuple of str
        Models of the ``lighting`` family (phong with two lights, phong with a shadowed
        directional light, the unlit solid frame, against llvmpipe): ``"demo"`` is the built-in
        demo model (``rasterkit.shapes.demo()``), any other name a shared OBJ.
    lighting_size : (width, height)
        Their image size.
    viewer_model, viewer_size
        The ``viewer`` family's model and picture size (:mod:`benchmarks.viewer`).
    viewer_moves, viewer_memory_drags
        Its timed mouse moves, and the drag events over which its memory is watched.
    """

    name: str
    warmup: int
    repeat: int
    models: tuple
    sizes: tuple
    fill_size: tuple
    fill_counts: tuple
    segments: int
    segment_size: tuple
    cli_model: str
    cli_size: tuple
    cold_runs: int
    sweep_triangles: tuple
    sweep_sizes: tuple
    sweep_model: str
    memory: tuple
    process_repeat: int
    startup_model: str = "stanford-bunny"
    startup_size: tuple = TARGET_SIZE
    demo_size: tuple | None = None
    startup_cold_runs: int = 1
    startup_sequence: bool = True
    first_model_runs: int = 1
    first_model_modes: tuple = ("solid",)
    contention_processes: tuple = (1, 2, 4)
    contention_seconds: float = 2.0
    aa_model: str = "ogre"
    aa_size: tuple = TARGET_SIZE
    cv_model: str = "ogre"
    cv_size: tuple = TARGET_SIZE
    svg_models: tuple = ("armadillo", "sportsCar")
    svg_size: tuple = TARGET_SIZE
    batch_size: tuple = (1280, 960)
    batch_models: tuple = ("stanford-bunny", "armadillo", "sponza", "lost_empire", "ogre", "sportsCar")
    texture_models: tuple = ("spot", "beast")
    texture_size: tuple = TARGET_SIZE
    textured_cold_runs: int = 1
    lit_cold_runs: int = 1
    lighting_models: tuple = ("demo", "stanford-bunny")
    lighting_size: tuple = TARGET_SIZE
    viewer_model: str = "sportsCar"
    viewer_size: tuple = (960, 720)
    viewer_moves: int = 120
    viewer_memory_drags: int = 1000


FULL = Settings(
    name="full", warmup=2, repeat=7,
    models=("suzanne", "spot", "stanford-bunny", "ogre", "sportsCar"),
    sizes=((640, 480), (1920, 1080), (3840, 2160)),
    fill_size=TARGET_SIZE, fill_counts=(50, 100, 200, 400),
    segments=1_000_000, segment_size=TARGET_SIZE,
    cli_model="stanford-bunny", cli_size=TARGET_SIZE, cold_runs=5,
    sweep_triangles=(16, 32, 64, 128, 256, 512),
    sweep_sizes=((320, 240), (640, 480), (1280, 720), (1920, 1080), (2560, 1440), (3840, 2160)),
    sweep_model="stanford-bunny", memory=("render", "fill", "lines2d", "loading"), process_repeat=5,
    startup_cold_runs=3, first_model_runs=3, contention_seconds=5.0,
    texture_models=("spot", "african_head", "fuze", "beast", "lost_empire"), textured_cold_runs=3, lit_cold_runs=3,
    lighting_models=("demo", "stanford-bunny", "ogre"),
)

QUICK = Settings(
    name="quick", warmup=1, repeat=5,
    models=("suzanne", "spot", "stanford-bunny"),
    sizes=((640, 480), TARGET_SIZE),
    fill_size=TARGET_SIZE, fill_counts=(200,),
    segments=100_000, segment_size=TARGET_SIZE,
    cli_model="spot", cli_size=(640, 480), cold_runs=0,
    sweep_triangles=(16, 64, 256),
    sweep_sizes=((320, 240), (1280, 720), (3840, 2160)),
    sweep_model="stanford-bunny", memory=("render",), process_repeat=3, first_model_runs=0,
)

TARGETS = Settings(
    name="targets", warmup=3, repeat=11,
    models=TARGET_MODELS,
    sizes=(TARGET_SIZE,),
    fill_size=TARGET_SIZE, fill_counts=(200,),
    segments=100_000, segment_size=TARGET_SIZE,
    cli_model="stanford-bunny", cli_size=TARGET_SIZE, cold_runs=0,
    sweep_triangles=(16,), sweep_sizes=((640, 480),),
    sweep_model="stanford-bunny", memory=("render",), process_repeat=3,
    texture_models=("spot", "beast", "lost_empire"),
)
"""Only what the targets need (``--targets``): the rasterization issue's three models at
1920x1080 in every mode, the 200-triangle fill scene and its thread scaling; the textured
frames of spot and the larger textured models; the lit frames of the demo model and the bunny."""

TINY = Settings(
    name="tiny", warmup=1, repeat=1,
    models=("suzanne",),
    sizes=((64, 48),),
    fill_size=(64, 48), fill_counts=(20,),
    segments=1000, segment_size=(64, 48),
    cli_model="suzanne", cli_size=(64, 48), cold_runs=0,
    sweep_triangles=(8, 16),
    sweep_sizes=((32, 24), (64, 48)),
    sweep_model="suzanne", memory=("render",), process_repeat=1,
    startup_model="suzanne", startup_size=(64, 48), demo_size=(64, 48), startup_cold_runs=1,
    startup_sequence=False, first_model_runs=0, contention_processes=(1, 2), contention_seconds=0.3,
    aa_model="suzanne", aa_size=(64, 48), cv_model="suzanne", cv_size=(64, 48),
    svg_models=("suzanne",), svg_size=(64, 48), batch_size=(64, 48), batch_models=("suzanne",),
    texture_models=("spot", "fuze"), texture_size=(64, 48), textured_cold_runs=0, lit_cold_runs=0,
    lighting_models=("demo",), lighting_size=(64, 48), viewer_model="suzanne", viewer_size=(64, 48),
    viewer_moves=20, viewer_memory_drags=100,
)


def model_path(name: str) -> Path:
    """Path of a shared model, ``MODELS_DIR / (name + '.obj')``."""
    return MODELS_DIR / f"{name}.obj"
