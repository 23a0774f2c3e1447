"""The command line (verify/cli/): outputs, options, errors."""
