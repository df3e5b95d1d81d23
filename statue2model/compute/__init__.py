"""Where runs execute and what they may ask of the machine: the executors that run
batches serially, on local processes or on a dask cluster (executors), and the
memory and run-count budgets checked before any large allocation (budget)."""
