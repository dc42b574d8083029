"""The worker process of :meth:`codesign.Task.optimize` (``python -m codesign.worker``): it
reads the run's setup and then one design per line on stdin, and answers each with one line on
stdout, as ``codesign worker`` does."""

from codesign._native import serve_worker


def main() -> None:
    """Serves evaluation requests until stdin closes."""
    serve_worker()


if __name__ == "__main__":
    main()
