"""Case and result records, their JSON Schemas, and the files they live in."""
