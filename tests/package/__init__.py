"""The package as a whole: its layers and names, the README, the docs, the install paths, the versions."""
