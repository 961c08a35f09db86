-- tests/premake/check.lua: keeps premake5.lua honest against the CMake build, without premake.
--
-- Usage: lua5.4 tests/premake/check.lua <repo_root> <libs> [<project>=<libs> ...]
--
-- premake5 is not packaged for Debian, so this script stands in for it: it defines stubs for the
-- premake API that premake5.lua and extern/premake5.lua use (workspace, project, files, links,
-- filter, include, ...), evaluates them as premake would on Linux with gcc and no command-line
-- options, for each configuration, and then checks that:
--   (a) every .cpp file under src/ is in exactly one project's files (glob patterns such as
--       src/core/**.cpp are resolved against the files `find` lists under <repo_root>);
--   (b) the system libraries (links that are not projects of the workspace) of the programs sdfgen
--       and sdfgen_tests, taken together, are exactly <libs>: a comma-separated list of library
--       base names, the ones CMake links those executables with (e.g. tbb,tinyobjloader,gtest,...).
--       Each optional <project>=<libs> argument checks one project's own list exactly as well;
--   (c) the projects exist with the right kinds, the programs link sdfgen_core, and sdfgen and
--       sdfgen_tests define SDFGEN_SOURCE_DIR as the quoted repository root, as CMake does.
-- Premake does not hand a static library's links on to the programs that use it, so (b) counts only
-- the links each program lists itself. The script prints what is missing or extra and exits 1 on
-- any mismatch (2 on a usage error, or if premake5.lua uses an API this stub does not model), and
-- prints one summary line on success.

local function usage(message)
   io.stderr:write("premake check: " .. message .. "\n",
      "usage: lua5.4 tests/premake/check.lua <repo_root> <lib,lib,...> [<project>=<lib,lib,...> ...]\n")
   os.exit(2)
end

local root = arg[1]
if not root or not arg[2] then usage("missing arguments") end
if root:sub(1, 1) ~= "/" then   -- absolute, like the paths premake works with
   local pipe = io.popen("cd '" .. root:gsub("'", "'\\''") .. "' && pwd")
   root = pipe:read("l") or usage("no directory " .. root)
   pipe:close()
end
root = root:gsub("/+$", "")
if root == "" then root = "/" end

local function split_list(s)
   local out = {}
   for item in s:gmatch("[^,%s]+") do out[#out + 1] = item end
   return out
end

local expected_union = nil
local expected_per_project = {}
for i = 2, #arg do
   local name, list = arg[i]:match("^([%w_%-]+)=(.*)$")
   if name then
      expected_per_project[name] = split_list(list)
   elseif expected_union then
      usage("more than one plain library list: " .. arg[i])
   else
      expected_union = split_list(arg[i])
   end
end
if not expected_union then usage("missing the library list") end

---------------------------------------------------------------------------------------------------
-- Paths and the repository's file list

local function shell_quote(s) return "'" .. s:gsub("'", "'\\''") .. "'" end

local function normalize(p)
   local absolute = p:sub(1, 1) == "/"
   local parts = {}
   for part in p:gmatch("[^/]+") do
      if part == ".." then
         if #parts > 0 and parts[#parts] ~= ".." then parts[#parts] = nil
         elseif not absolute then parts[#parts + 1] = part end
      elseif part ~= "." then
         parts[#parts + 1] = part
      end
   end
   local out = table.concat(parts, "/")
   if absolute then return "/" .. out end
   return out == "" and "." or out
end

local function join(dir, p)
   if p:sub(1, 1) == "/" then return normalize(p) end
   return normalize(dir .. "/" .. p)
end

-- Root-relative form of an absolute path inside the repository, or nil.
local function relative_to_root(abs)
   if abs == root then return "." end
   local prefix = root == "/" and "/" or root .. "/"
   if abs:sub(1, #prefix) == prefix then return abs:sub(#prefix + 1) end
   return nil
end

local repo_files = {}
do
   local cmd = "cd " .. shell_quote(root) .. " && find . \\( -name .git -o -name node_modules -o -path './build*' \\) -prune"
      .. " -o -type f -print"
   local pipe = io.popen(cmd)
   for line in pipe:lines() do repo_files[#repo_files + 1] = line:gsub("^%./", "") end
   local ok = pipe:close()
   if not ok or #repo_files == 0 then usage("cannot list the files under " .. root) end
   table.sort(repo_files)
end

local function has_wildcard(p) return p:find("*", 1, true) ~= nil end

-- premake globs: "**" matches across directories, "*" within one path component.
local function glob_to_pattern(glob)
   local out = glob:gsub("[%^%$%(%)%%%.%[%]%+%-%?]", "%%%0")
   out = out:gsub("%*%*", "\1"):gsub("%*", "[^/]*"):gsub("\1", ".*")
   return "^" .. out .. "$"
end

local function match_files(abs_glob)
   local rel = relative_to_root(abs_glob)
   if not rel then return nil end   -- a glob outside the repository: not resolvable here
   local pattern, out = glob_to_pattern(rel), {}
   for _, f in ipairs(repo_files) do
      if f:match(pattern) then out[#out + 1] = f end
   end
   return out
end

---------------------------------------------------------------------------------------------------
-- The premake stub: records every API call with the filter and script directory it was made under.

local workspaces, projects, project_order = {}, {}, {}
local current_ws, current_prj, current_filter = nil, nil, {}
local script_dirs = {}
local problems, notes = {}, {}

local function problem(msg) problems[#problems + 1] = msg end

local function script_dir() return script_dirs[#script_dirs] end

local function flatten(value, out)
   out = out or {}
   if type(value) == "table" then
      for _, v in ipairs(value) do flatten(v, out) end
   elseif value ~= nil then
      out[#out + 1] = tostring(value)
   end
   return out
end

local function record(field, value)
   local scope = current_prj or current_ws
   if not scope then
      io.stderr:write("premake check: " .. field .. " called outside any workspace or project\n")
      os.exit(2)
   end
   scope.records[#scope.records + 1] = {
      field = field, values = flatten(value), filter = current_filter, dir = script_dir(),
   }
end

local env = {}

-- premake API functions this stub accepts and records without interpreting.
local API_NAMES = {
   "location", "configurations", "platforms", "architecture", "startproject", "language",
   "cppdialect", "cdialect", "targetdir", "objdir", "targetname", "targetprefix", "targetextension",
   "optimize", "symbols", "warnings", "externalwarnings", "buildoptions", "linkoptions", "defines",
   "undefines", "includedirs", "externalincludedirs", "sysincludedirs", "libdirs", "syslibdirs",
   "prebuildcommands", "prebuildmessage", "postbuildcommands", "postbuildmessage", "prelinkcommands",
   "buildcommands", "buildoutputs", "buildinputs", "buildmessage", "vpaths", "flags", "staticruntime",
   "runtime", "systemversion", "toolset", "debugdir", "debugargs", "pic", "rtti", "exceptionhandling",
   "entrypoint", "disablewarnings", "enablewarnings", "fatalwarnings", "dependson", "linkgroups",
   "rules", "characterset", "floatingpoint", "vectorextensions", "editandcontinue", "kind", "files",
   "removefiles", "links", "removelinks", "forceincludes", "sanitize", "omitframepointer",
   "intrinsics", "inlining", "linktimeoptimization", "compileas", "buildaction", "visibility",
}
for _, name in ipairs(API_NAMES) do
   env[name] = function(value) record(name, value) end
end

function env.newoption(opt)
   if type(opt) ~= "table" or not opt.trigger then
      io.stderr:write("premake check: newoption needs a table with a trigger\n")
      os.exit(2)
   end
end

function env.workspace(name)
   local ws = workspaces[name]
   if not ws then
      ws = { name = name, records = {} }
      workspaces[name] = ws
   end
   current_ws, current_prj, current_filter = ws, nil, {}
end
env.solution = env.workspace

function env.project(name)
   if not current_ws then
      io.stderr:write("premake check: project " .. tostring(name) .. " outside any workspace\n")
      os.exit(2)
   end
   local prj = projects[name]
   if not prj then
      prj = { name = name, workspace = current_ws, records = {}, dir = script_dir() }
      projects[name] = prj
      project_order[#project_order + 1] = name
   end
   current_prj, current_filter = prj, {}
end

function env.group() end

function env.filter(terms)
   current_filter = flatten(terms)
end

local function run_script(file)
   local chunk, err = loadfile(file, "t", env)
   if not chunk then
      io.stderr:write("premake check: " .. err .. "\n")
      os.exit(2)
   end
   script_dirs[#script_dirs + 1] = normalize(file:match("^(.*)/[^/]*$") or ".")
   env._SCRIPT = file
   env._SCRIPT_DIR = script_dir()
   local ok, result = pcall(chunk)
   if not ok then
      io.stderr:write("premake check: error evaluating " .. file .. ": " .. tostring(result) .. "\n")
      os.exit(2)
   end
   script_dirs[#script_dirs] = nil
   env._SCRIPT_DIR = script_dir()
   return result
end

local function shell_test(flag, p)
   return os.execute("test " .. flag .. " " .. shell_quote(p)) == true
end
local function is_file(p) return shell_test("-f", p) end
local function is_dir(p) return shell_test("-d", p) end

function env.include(name)
   local p = join(script_dir(), name)
   if is_dir(p) then p = p .. "/premake5.lua" end
   if not is_file(p) then
      io.stderr:write("premake check: include: no " .. p .. "\n")
      os.exit(2)
   end
   return run_script(p)
end

-- Standard Lua, plus premake's path, os and premake tables as far as the scripts need them.
for _, name in ipairs({ "assert", "error", "ipairs", "next", "pairs", "pcall", "print", "select",
                        "tonumber", "tostring", "type", "unpack", "xpcall", "string", "table",
                        "math", "setmetatable", "getmetatable", "rawget", "rawset" }) do
   env[name] = _G[name]
end
env.unpack = env.unpack or table.unpack

env.path = {
   join = function(...)
      local out = nil
      for _, p in ipairs({ ... }) do out = out and join(out, p) or p end
      return out and normalize(out)
   end,
   getabsolute = function(p) return join(script_dir(), p) end,
   translate = function(p, sep) return (p:gsub("[/\\]", sep or "/")) end,
   getdirectory = function(p) return p:match("^(.*)/[^/]*$") or "." end,
   getname = function(p) return p:match("([^/]*)$") end,
   getbasename = function(p) return (p:match("([^/]*)$"):gsub("%.[^.]*$", "")) end,
   getextension = function(p) return p:match("(%.[^./]*)$") or "" end,
   isabsolute = function(p) return p:sub(1, 1) == "/" end,
}

env.os = {
   getenv = os.getenv, time = os.time, date = os.date, clock = os.clock,
   getcwd = function() return script_dir() end,
   isfile = is_file,
   isdir = is_dir,
   execute = function() return true end,   -- never run generators (glad) from a check
   host = function() return "linux" end,
   target = function() return "linux" end,
   ishost = function(s) return s == "linux" end,
   istarget = function(s) return s == "linux" end,
   matchfiles = function(...)
      local out = {}
      for _, glob in ipairs(flatten({ ... })) do
         for _, f in ipairs(match_files(join(script_dir(), glob)) or {}) do out[#out + 1] = root .. "/" .. f end
      end
      return out
   end,
}

env.premake = {
   warn = function(...) notes[#notes + 1] = "premake.warn: " .. string.format(...) end,
   info = function() end,
   error = function(...) error(string.format(...), 2) end,
}

env._OPTIONS = {}
env._MAIN_SCRIPT = root .. "/premake5.lua"
env._MAIN_SCRIPT_DIR = root

local NIL_GLOBALS = { _ACTION = true }   -- premake globals that are nil here: no action is run
setmetatable(env, {
   __index = function(_, name)
      if NIL_GLOBALS[name] then return nil end
      io.stderr:write("premake check: the premake scripts use `" .. tostring(name) .. "`, which check.lua"
         .. " does not model; add it to check.lua's stub (or fix the name)\n")
      os.exit(2)
   end,
})

run_script(root .. "/premake5.lua")

---------------------------------------------------------------------------------------------------
-- Evaluate the records for Linux, gcc, no options, per configuration.

local function values_for(field_value, prj, cfgname)
   local key = field_value
   if key == "configurations" then return { cfgname } end
   if key == "system" then return { "linux" } end
   if key == "toolset" then return { "gcc" } end
   if key == "action" then return { "gmake2" } end
   if key == "architecture" then return { "x86_64" } end
   if key == "platforms" then return {} end
   if key == "options" then return {} end
   if key == "kind" then return { prj.kind or "" } end
   if key == "language" then return { prj.language or "" } end
   return nil
end

local function wildcard_match(value, pattern)
   local p = pattern:lower():gsub("[%^%$%(%)%%%.%[%]%+%-%?]", "%%%0"):gsub("%*", ".*")
   return value:lower():match("^" .. p .. "$") ~= nil
end

-- Does one filter term, such as "toolset:not msc*" or "configurations:Debug or Release", hold?
-- Like premake: words joined by " or ", each optionally negated with "not " and prefixed with a
-- field ("configurations" when none is given; a prefix carries over to the following words).
local function term_holds(term, prj, cfgname)
   local prefix = "configurations"
   for word in (term:lower() .. " or "):gmatch("%s*(.-)%s+or%s+") do
      local assertion = true
      while true do
         if word:sub(1, 4) == "not " then
            assertion, word = not assertion, word:sub(5)
         elseif word:find(":", 1, true) then
            prefix, word = word:match("^([^:]*):(.*)$")
         else
            break
         end
      end
      if prefix == "files" then return false end   -- per-file settings do not apply to a whole project
      local values = values_for(prefix, prj, cfgname)
      if not values then
         io.stderr:write("premake check: filter prefix `" .. prefix .. "` is not modelled by check.lua\n")
         os.exit(2)
      end
      local matched = false
      for _, v in ipairs(values) do
         if wildcard_match(v, word) then matched = true break end
      end
      if matched == assertion then return true end
   end
   return false
end

local function filter_holds(filter, prj, cfgname)
   for _, term in ipairs(filter) do
      if not term_holds(term, prj, cfgname) then return false end
   end
   return true
end

local function configurations_of(ws)
   local out = {}
   for _, r in ipairs(ws.records) do
      if r.field == "configurations" then
         for _, v in ipairs(r.values) do out[#out + 1] = v end
      end
   end
   return out
end

-- The records that apply to a project in one configuration: its workspace's, then its own.
local function active_records(prj, cfgname, field)
   local out = {}
   for _, scope in ipairs({ prj.workspace, prj }) do
      for _, r in ipairs(scope.records) do
         if r.field == field and filter_holds(r.filter, prj, cfgname) then out[#out + 1] = r end
      end
   end
   return out
end

local function first_value(prj, cfgname, field)
   local value = nil
   for _, r in ipairs(active_records(prj, cfgname, field)) do value = r.values[1] end
   return value
end

local function strip_link(name)
   name = name:gsub(":static$", ""):gsub(":shared$", "")
   return name
end

local function sorted_keys(set)
   local out = {}
   for k in pairs(set) do out[#out + 1] = k end
   table.sort(out)
   return out
end

local function set_of(list)
   local s = {}
   for _, v in ipairs(list) do s[v] = true end
   return s
end

-- Compare a set of libraries with the expected list; report missing and extra ones.
local function compare_libs(what, actual, expected_list)
   local expected = set_of(expected_list)
   local missing, extra = {}, {}
   for _, lib in ipairs(sorted_keys(expected)) do
      if not actual[lib] then missing[#missing + 1] = lib end
   end
   for _, lib in ipairs(sorted_keys(actual)) do
      if not expected[lib] then extra[#extra + 1] = lib end
   end
   if #missing > 0 then problem(what .. ": missing " .. table.concat(missing, ", ") .. " (CMake links them)") end
   if #extra > 0 then problem(what .. ": extra " .. table.concat(extra, ", ") .. " (CMake does not link them)") end
end

local ws_count = 0
for _ in pairs(workspaces) do ws_count = ws_count + 1 end
if ws_count ~= 1 then problem("expected one workspace, found " .. ws_count) end

local all_configs = {}
for _, name in ipairs(project_order) do
   local prj = projects[name]
   local configs = configurations_of(prj.workspace)
   if #configs == 0 then problem("workspace " .. prj.workspace.name .. " has no configurations") end
   prj.configs = configs
   for _, c in ipairs(configs) do all_configs[c] = true end
   prj.language = first_value(prj, configs[1] or "", "language")
   prj.kind = first_value(prj, configs[1] or "", "kind")
   for _, c in ipairs(configs) do
      if first_value(prj, c, "kind") ~= prj.kind then
         problem("project " .. name .. " changes its kind between configurations")
      end
   end
end

-- Files: a project's files are those its files{} calls match in any configuration, less removefiles.
local owners = {}   -- root-relative path -> list of project names
for _, name in ipairs(project_order) do
   local prj = projects[name]
   local set = {}
   for _, c in ipairs(prj.configs) do
      for _, field in ipairs({ "files", "removefiles" }) do
         for _, r in ipairs(active_records(prj, c, field)) do
            for _, glob in ipairs(r.values) do
               local abs = join(r.dir, glob)
               local matched
               if has_wildcard(abs) then
                  matched = match_files(abs)
                  if matched and #matched == 0 and field == "files" then
                     notes[#notes + 1] = "note: " .. name .. ": " .. glob .. " matches no file"
                  end
               else
                  matched = { relative_to_root(abs) or abs }
               end
               for _, f in ipairs(matched or {}) do set[f] = (field == "files") or nil end
            end
         end
      end
   end
   prj.files = set
   for f in pairs(set) do
      owners[f] = owners[f] or {}
      table.insert(owners[f], name)
   end
end

-- (a) every .cpp under src/ in exactly one project.
local source_count = 0
for _, f in ipairs(repo_files) do
   if f:match("^src/.*%.cpp$") then
      source_count = source_count + 1
      local who = owners[f] or {}
      table.sort(who)
      if #who == 0 then
         problem(f .. " is in no project's files")
      elseif #who > 1 then
         problem(f .. " is in more than one project's files: " .. table.concat(who, ", "))
      end
   end
end
if source_count == 0 then problem("found no .cpp file under " .. root .. "/src") end

-- (c) structure.
local wanted_kinds = {
   sdfgen_core = "StaticLib", sdfgen_openvdb = "SharedLib", sdfgen_assimp = "SharedLib", sdfgen = "ConsoleApp", sdfgen_tests = "ConsoleApp",
   glad = "StaticLib", sdfgen_imgui = "StaticLib",
}
for _, name in ipairs(sorted_keys(wanted_kinds)) do
   local prj = projects[name]
   if not prj then
      problem("no project " .. name)
   elseif prj.kind ~= wanted_kinds[name] then
      problem("project " .. name .. " is kind " .. tostring(prj.kind) .. ", expected " .. wanted_kinds[name])
   end
end

local function system_links(prj, cfgname)
   local libs, siblings = {}, {}
   for _, r in ipairs(active_records(prj, cfgname, "links")) do
      for _, l in ipairs(r.values) do
         l = strip_link(l)
         if projects[l] then siblings[l] = true else libs[l] = true end
      end
   end
   for _, r in ipairs(active_records(prj, cfgname, "removelinks")) do
      for _, l in ipairs(r.values) do libs[strip_link(l)], siblings[strip_link(l)] = nil, nil end
   end
   return libs, siblings
end

-- (b) system libraries of the programs, per configuration.
local programs = { "sdfgen", "sdfgen_tests" }
for _, c in ipairs(sorted_keys(all_configs)) do
   local union, seen = {}, {}
   for _, name in ipairs(programs) do
      local prj = projects[name]
      if prj then
         seen[#seen + 1] = name
         local libs, siblings = system_links(prj, c)
         for lib in pairs(libs) do union[lib] = true end
         if not siblings["sdfgen_core"] then problem(name .. " [" .. c .. "] does not link sdfgen_core") end
      end
   end
   compare_libs(table.concat(seen, " + ") .. " [" .. c .. "] system libraries", union, expected_union)
   for _, name in ipairs(sorted_keys(expected_per_project)) do
      if not projects[name] then
         problem("no project " .. name .. " (named on the command line)")
      else
         local libs = system_links(projects[name], c)
         compare_libs(name .. " [" .. c .. "] system libraries", libs, expected_per_project[name])
      end
   end
end

-- (c) SDFGEN_SOURCE_DIR, with which the CLI and the tests find assets/bunny.obj.
for _, name in ipairs(programs) do
   local prj = projects[name]
   local want = 'SDFGEN_SOURCE_DIR="' .. root .. '"'
   for _, c in ipairs(prj and prj.configs or {}) do
      local found = false
      for _, r in ipairs(active_records(prj, c, "defines")) do
         for _, d in ipairs(r.values) do
            if d == want then found = true end
         end
      end
      if not found then problem(name .. " [" .. c .. "] does not define " .. want) end
   end
end

local printed = {}
for _, n in ipairs(notes) do
   if not printed[n] then print("premake check: " .. n) end
   printed[n] = true
end
if #problems > 0 then
   for _, p in ipairs(problems) do print("premake check: FAIL: " .. p) end
   os.exit(1)
end
local libs = {}
for _, l in ipairs(expected_union) do libs[#libs + 1] = l end
table.sort(libs)
print(string.format("premake check: OK: %d .cpp files under src/ each in one of %d projects; sdfgen and "
   .. "sdfgen_tests link %s, as CMake does", source_count, #project_order, table.concat(libs, ", ")))
