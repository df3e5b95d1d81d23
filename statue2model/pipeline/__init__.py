"""The run: its stages (each conducts: it calls the analyses and hands plain data to
report/), their content-hash cache, the project file and the Body kept once per run.

Modules: ``config`` (the project file), ``cache`` (stage keys and folders), ``body_cache``
(the Body built once per run, kept beside props.json), ``stages``, ``run`` (one scan, a
folder of scans).
"""
