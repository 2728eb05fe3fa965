"""Writes the report's files only when their bytes change, so that a regenerated report leaves
unchanged files (and their history) alone; PNG files carry no version or date, so the same plot
gives the same bytes."""
import io
import os
import tempfile

# No "Software: Matplotlib version ..." chunk: the same plot is the same file on any version.
PNG_METADATA = {"Software": None}


def write_bytes(path, data):
    """Writes data to path unless path already holds exactly data; True when it wrote."""
    try:
        with open(path, "rb") as f:
            if f.read() == data:
                return False
    except FileNotFoundError:
        pass
    folder = os.path.dirname(os.path.abspath(path))
    fd, temporary = tempfile.mkstemp(dir=folder, prefix=".tmp_", suffix=os.path.basename(path))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise
    return True


def write_text(path, text):
    return write_bytes(path, text.encode("utf-8"))


def save_figure(fig, path, **options):
    """fig.savefig(path, **options) as PNG, written only when the image changed."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", metadata=PNG_METADATA, **options)
    return write_bytes(path, buffer.getvalue())
