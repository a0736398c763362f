"""A local Dask cluster shared by the plane tests (2 worker processes, 1 thread each)."""
import pytest


@pytest.fixture(scope="module")
def cluster():
    import logging

    from distributed import Client, LocalCluster
    cl = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, silence_logs=logging.ERROR)
    client = Client(cl, set_as_default=False)
    yield cl, client
    client.close()
    cl.close()
