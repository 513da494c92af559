#pragma once
// Columns a table gained after files with it were written: an old file
// opened to write gets them (ALTER TABLE ... ADD COLUMN), and one opened
// read-only is read with a SELECT naming only the columns it has (NULL for
// the others), so no older mission becomes unreadable.
#include <set>
#include <string>
#include <vector>

struct sqlite3;

namespace seamap {

struct SqlColumn {
  const char* name;
  const char* type;  // SQLite type name, e.g. "real"
};

// The table's column names (PRAGMA table_info); empty when there is no such table.
// Throws std::runtime_error when SQLite fails.
std::set<std::string> TableColumns(sqlite3* db, const std::string& table);

// Adds each of `columns` the table lacks. Throws std::runtime_error naming the column.
void AddMissingColumns(sqlite3* db, const std::string& table, const std::vector<SqlColumn>& columns);

// "a, NULL, c": `wanted` as a select list, NULL where the table lacks the column,
// so result column i is always wanted[i].
std::string SelectList(const std::set<std::string>& present, const std::vector<std::string>& wanted);

}  // namespace seamap
