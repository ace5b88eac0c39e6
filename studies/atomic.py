"""Command outputs that appear whole or not at all: :mod:`softcath.core.atomic`, under its older path."""

from softcath.core.atomic import (
    Outputs,
    atomic_path,
    check_finite_json,
    check_outputs,
    check_parent,
    folder_lock,
    forget_created_dirs,
    pid_alive,
    prepare_out_dir,
    remove_created_dirs,
    remove_stale_temps,
    staged_dir,
    unstage,
    write_json,
    write_text,
)

__all__ = [
    "prepare_out_dir",
    "check_parent",
    "check_outputs",
    "atomic_path",
    "write_text",
    "write_json",
    "check_finite_json",
    "Outputs",
    "staged_dir",
    "unstage",
    "remove_stale_temps",
    "pid_alive",
    "remove_created_dirs",
    "folder_lock",
    "forget_created_dirs",
]
