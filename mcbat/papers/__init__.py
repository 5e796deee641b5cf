"""Reproductions of papers, one subpackage each. Only the command line imports them."""

__all__ = []
