"""sssbake from Python: running batches of the `sssbake` binary on a Dask
cluster (`sssbake.farm`)."""
