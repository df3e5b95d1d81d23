"""Output files and bundled data: atomic writes, output folders and their locks and
manifests, JSON and spreadsheet-safe CSV (files, csvsafe), and where the bundled
scans live (paths)."""
