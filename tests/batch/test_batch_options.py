"""A batch on local workers draws with every field of RenderOptions, as render() does: the
images of ``jobs=2`` equal, bit for bit, the API's frames with the same options and view
(tests/core/test_render_options.py shows that each field changes those frames; on Dask:
tests/batch/test_batch_dask.py)."""

from __future__ import annotations

from support.frames import batch_matches_the_api, model_folder


def test_a_batch_on_two_local_workers_draws_every_field(tmp_path):
    batch_matches_the_api(model_folder(tmp_path / "models"), tmp_path / "out", jobs=2)
