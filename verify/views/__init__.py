"""Views: text and JSON for the command line, the report pages, the figures."""
