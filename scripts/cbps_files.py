"""Files written whole or not at all, and the non-finite numbers of JSON, for cbps's scripts
(scripts/*.py and validation/*.py). Standard library only; import it with scripts/ on sys.path
(the scripts beside it find it by themselves); nothing here imports a test.

Whole or not at all: every file goes to a hidden temporary file beside it, ".NAME.cbps-tmp-PID"
(the name cbps's own writers use, include/cbps/io/output_file.hpp), which is renamed over NAME
(os.replace, atomic on one file system) once it is complete; on any failure the temporary file
is removed and NAME keeps its old content. The new file has the permissions a plain open()
gives (0666 less the umask).

Non-finite numbers in JSON, which has none: as `number_json` (include/cbps/io/json_numbers.hpp) writes them
(docs/outputs.md, "JSON numbers"), inf, -inf and NaN are the strings "inf", "-inf" and "nan".
The writers here turn every non-finite float into those strings and never write Python's
non-standard NaN/Infinity tokens (allow_nan=False); null keeps its meaning in each format (no
value: not measured, not applicable; `cbps run`'s summary.json and `cbps converge`/`profile`
also write a non-finite value as null). read_number takes the strings back as floats.
"""
import contextlib
import json
import math
import os

NON_FINITE = {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}


# ---------------------------------------------------------------------------------------------
# Whole or not at all.


def temporary_name(path):
    """".NAME.cbps-tmp-PID" in PATH's folder, as cbps's temporary_name (src/io/output_file.cpp)."""
    folder, name = os.path.split(os.path.abspath(path))
    return os.path.join(folder, f".{name}.cbps-tmp-{os.getpid()}")


def _remove(temp):
    with contextlib.suppress(FileNotFoundError):
        os.unlink(temp)


@contextlib.contextmanager
def replacing(path):
    """`with replacing(PATH) as temp:` write the file named temp; when the block ends without an
    exception it is renamed over PATH, else removed (PATH untouched)."""
    temp = temporary_name(path)
    try:
        yield temp
        os.replace(temp, path)
    except BaseException:
        _remove(temp)
        raise


def write_text(path, text, encoding="utf-8"):
    """TEXT into PATH, whole or not at all."""
    with replacing(path) as temp:
        with open(temp, "w", encoding=encoding) as f:
            f.write(text)


def save_figure(fig, outputs):
    """A matplotlib figure into every file of OUTPUTS, {path: savefig keywords} (e.g.
    {"x.png": {"dpi": 150}, "x.svg": {}}), the format from each name's extension unless the
    keywords give one. All are drawn into their temporary files first and renamed only when every
    one is complete, so the files stay a matching set."""
    temps = []
    try:
        for path, keywords in outputs.items():
            keywords = dict(keywords)
            keywords.setdefault("format", os.path.splitext(path)[1].lstrip(".").lower())
            temp = temporary_name(path)
            temps.append((temp, path))
            fig.savefig(temp, **keywords)
        for temp, path in temps:
            os.replace(temp, path)
    finally:
        for temp, _ in temps:  # whatever was not renamed
            _remove(temp)


# ---------------------------------------------------------------------------------------------
# Numbers in JSON.


def json_number(x):
    """x for JSON as number_json writes it: a finite float as itself, inf, -inf and NaN as the
    strings "inf", "-inf" and "nan"; anything else (None, an int, a string) unchanged."""
    if isinstance(x, float) and not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return x


def json_ready(data):
    """DATA (dicts, lists, tuples, numbers, strings, None) with every float passed through
    json_number, for json.dumps(..., allow_nan=False). numpy's float64 is a float; other numpy
    scalars are not converted (convert them with float() or int() first)."""
    if isinstance(data, dict):
        return {k: json_ready(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [json_ready(v) for v in data]
    return json_number(data)


def json_text(data, indent=1, **keywords):
    """DATA as JSON text ending in a newline, non-finite floats as strings; keywords go to
    json.dumps (sort_keys, separators, ...)."""
    return json.dumps(json_ready(data), indent=indent, allow_nan=False, **keywords) + "\n"


def write_json(path, data, indent=1, **keywords):
    """DATA as JSON (json_text) into PATH, whole or not at all."""
    write_text(path, json_text(data, indent=indent, **keywords))


def read_number(value):
    """A number of a JSON file: an int or float as a float, "inf", "-inf" and "nan" as the
    float they stand for, None as None. ValueError for anything else."""
    if value is None:
        return None
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, str) and value in NON_FINITE:
        return NON_FINITE[value]
    raise ValueError(f"not a number: {value!r}")
