"""Speed benchmarks of mcbat: ``python -m benchmarks NAME|all|list|render`` (README.md)."""
