// Placeholder so the library has a source until the grammar lands (removed by it).
