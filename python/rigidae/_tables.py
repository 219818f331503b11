"""Tables for the user: pandas DataFrames when pandas is importable, else
dicts of numpy arrays (one per column, in the file's column order)."""
import csv
import math

import numpy as np

try:  # optional: Debian's python3-pandas
    import pandas as _pd
except ImportError:  # pragma: no cover - depends on the machine
    _pd = None

HAVE_PANDAS = _pd is not None


def _column(values):
    """int64 when every entry is an integer, float64 when every entry is a
    number (empty = NaN), else str."""
    try:
        return np.array([int(v) for v in values], dtype=np.int64)
    except ValueError:
        pass
    try:
        return np.array([float(v) if v != "" else math.nan for v in values], dtype=np.float64)
    except ValueError:
        return np.array(values, dtype=str)


def read_csv(path, as_dataframe=None):
    """A rigidae CSV file (comment lines start with '#') as a table."""
    with open(path, newline="", encoding="utf-8", errors="replace") as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    header, body = rows[0], rows[1:]
    columns = {name: _column([r[i] if i < len(r) else "" for r in body]) for i, name in enumerate(header)}
    return table(columns, as_dataframe)


def table(columns, as_dataframe=None):
    """dict of arrays -> DataFrame (pandas present and as_dataframe not False) or the dict."""
    if as_dataframe is None:
        as_dataframe = HAVE_PANDAS
    if as_dataframe:
        if not HAVE_PANDAS:
            raise ImportError("as_dataframe=True needs pandas (Debian: python3-pandas)")
        return _pd.DataFrame(columns)
    return columns
