#include "core/tiles/sqlite_columns.h"

#include <sqlite3.h>

#include <stdexcept>

namespace seamap {

std::set<std::string> TableColumns(sqlite3* db, const std::string& table) {
  std::set<std::string> out;
  sqlite3_stmt* s = nullptr;
  const std::string sql = "PRAGMA table_info(\"" + table + "\")";
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
    sqlite3_finalize(s);
    throw std::runtime_error("read the columns of " + table + ": " + sqlite3_errmsg(db));
  }
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    const unsigned char* name = sqlite3_column_text(s, 1);  // cid, name, type, notnull, dflt_value, pk
    if (name) out.insert(reinterpret_cast<const char*>(name));
  }
  sqlite3_finalize(s);
  if (rc != SQLITE_DONE) throw std::runtime_error("read the columns of " + table + ": " + sqlite3_errmsg(db));
  return out;
}

void AddMissingColumns(sqlite3* db, const std::string& table, const std::vector<SqlColumn>& columns) {
  const std::set<std::string> present = TableColumns(db, table);
  for (const SqlColumn& c : columns) {
    if (present.count(c.name)) continue;
    const std::string sql = "ALTER TABLE \"" + table + "\" ADD COLUMN " + c.name + " " + c.type;
    if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK)
      throw std::runtime_error("add column " + table + "." + c.name + ": " + sqlite3_errmsg(db));
  }
}

std::string SelectList(const std::set<std::string>& present, const std::vector<std::string>& wanted) {
  std::string out;
  for (const std::string& name : wanted) {
    if (!out.empty()) out += ", ";
    out += present.count(name) ? name : "NULL";
  }
  return out;
}

}  // namespace seamap
